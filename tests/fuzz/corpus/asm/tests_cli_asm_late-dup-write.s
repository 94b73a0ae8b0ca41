# machine: os
# The fdiv (4 cycles) and the fadd issued 3 cycles later both write f1 in the same cycle.
        fdiv f1, f2, f3
        nop
        nop
        fadd f1, f4, f5
        halt
