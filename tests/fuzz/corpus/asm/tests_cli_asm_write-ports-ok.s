# machine: os
        { fadd f1, f2, f3 ; fadd f4, f5, f6 }
        flw f7, 0(r1)
        halt
