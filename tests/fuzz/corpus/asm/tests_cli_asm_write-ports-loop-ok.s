# machine: os
# write-ports-loop.s fixed: the fadd issues a cycle earlier, so its result lands before the fdivs'.
        li r1, 4
loop:   addi r1, r1, -1
        fadd f7, f8, f9
        nop
        { fdiv f1, f2, f3 ; fdiv f4, f5, f6 ; bnez r1, loop }
        halt
