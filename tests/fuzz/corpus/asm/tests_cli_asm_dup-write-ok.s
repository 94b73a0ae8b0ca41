# machine: os
# Bundle semantics: reads see the old values, so this swaps r0 and r1.
        { mov r0, r1 ; mov r1, r0 }
        halt
