# machine: os
# A load outside every memory region in the fourth bundle: every engine (fast, checked and
# lock-step) stops with a mem-range fault after 3 cycles, the faulting bundle not issued.
        li r1, 1
        nop
        { li r2, 0x7ffffff0 ; addi r1, r1, 1 }
        lw r3, 0(r2)
        halt
