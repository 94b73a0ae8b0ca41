# machine: os
        { fmul f1, f2, f3 ; fadd f4, f5, f6 }
        halt
