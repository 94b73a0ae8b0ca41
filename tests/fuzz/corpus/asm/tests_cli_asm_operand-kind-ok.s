# machine: os
        add r1, r2, r3
        lw r4, 8(r5)
        halt
