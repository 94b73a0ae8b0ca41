# machine: os
# Two operations of one bundle write r1 in the same cycle.
        { add r1, r2, r3 ; sub r1, r4, r5 }
        halt
