# machine: os
# An integer add pinned to a floating-point unit.
        fpu0: add r1, r2, r3
        halt
