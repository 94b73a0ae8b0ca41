# machine: os
        iu1: add r1, r2, r3
        halt
