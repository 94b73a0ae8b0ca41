# machine: os
        { sel r1, r2, r3, r4 ; add r5, r6, r7 }
        halt
