# machine: os
# The fdiv (4 cycles) is still in flight when the fadd issued one bundle later writes f1: the
# fadd's result would land first and the fdiv's older value over it.
        fdiv f1, f2, f3
        fadd f1, f4, f5
        halt
