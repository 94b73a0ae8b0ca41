# machine: os
        fdiv f1, f2, f3
        nop
        nop
        fadd f6, f4, f5
        halt
