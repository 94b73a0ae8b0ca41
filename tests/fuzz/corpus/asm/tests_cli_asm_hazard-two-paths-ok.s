# machine: os
# hazard-two-paths.s fixed: the prologue waits for its fdiv, the loop body for the one it issues.
        fdiv f1, f2, f3
        li r1, 4
        nop
        nop
loop:   fadd f2, f1, f1
        addi r1, r1, -1
        fdiv f1, f2, f3
        nop
        nop
        bnez r1, loop
        halt
