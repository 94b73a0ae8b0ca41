# machine: os
# swap: bundle semantics. Every operation of a bundle reads its sources before any result is
# written, so the second bundle exchanges r0 and r1 (and f0/f1) without a temporary register.
# After it: r0 = 42, r1 = 17, f0 = 2.5, f1 = -1.0.
        { li r0, 17 ; li r1, 42 ; fli f0, -1.0 ; fli f1, 2.5 }
        { mov r0, r1 ; mov r1, r0 ; fmov f0, f1 ; fmov f1, f0 }
        halt
