# machine: os
# fdiv takes 4 cycles on os: its result is read one cycle too early.
        fdiv f1, f2, f3
        fadd f4, f5, f6
        fadd f7, f8, f9
        fmul f10, f1, f1
        halt
