# machine: os
# A latency-1 result is readable by the very next bundle; fdiv's after 4 cycles.
        fdiv f1, f2, f3
        fadd f4, f5, f6
        fadd f7, f4, f4
        fadd f8, f7, f7
        fmul f10, f1, f1
        halt
