# machine: os
        { fpu1: fadd f1, f2, f3 ; fpu0: fmul f4, f5, f6 }
        halt
