# machine: os
# Three stores, but only the two integer units accept memory operations.
        { fsw f1, 0(r9) ; fsw f2, 4(r9) ; fsw f3, 8(r9) }
        halt
