# machine: os
# A float register where an integer register belongs, and a bad memory operand.
        add r1, f2, r3
        lw r4, r5
        halt
