# machine: os
        { fsw f1, 0(r9) ; fsw f2, 4(r9) }
        fsw f3, 8(r9)
        halt
