# machine: os
# Two operations pinned to the same slot.
        { fpu1: fadd f1, f2, f3 ; fpu1: fmul f4, f5, f6 }
        halt
