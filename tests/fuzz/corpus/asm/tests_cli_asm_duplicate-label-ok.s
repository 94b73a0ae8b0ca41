# machine: os
top:    add r1, r2, r3
bottom: halt
