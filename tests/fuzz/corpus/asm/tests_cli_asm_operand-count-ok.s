# machine: os
        add r1, r2, r3
        halt
