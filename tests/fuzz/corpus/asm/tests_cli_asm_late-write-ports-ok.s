# machine: os
        { fdiv f1, f2, f3 ; fdiv f4, f5, f6 }
        nop
        fadd f7, f8, f9
        nop
        halt
