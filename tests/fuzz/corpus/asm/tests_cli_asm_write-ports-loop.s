# machine: os
# Two fdivs at the bottom of the loop land, around the back edge, in the cycle of the next
# iteration's fadd: three FPRF writes in one cycle against two ports.
        li r1, 4
loop:   addi r1, r1, -1
        nop
        fadd f7, f8, f9
        { fdiv f1, f2, f3 ; fdiv f4, f5, f6 ; bnez r1, loop }
        halt
