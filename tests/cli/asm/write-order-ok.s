# machine: os
# A later write to a register whose earlier write is still in flight is fine when it lands
# strictly after it: the second fdiv lands one cycle after the first; the fadd issues once both
# have landed.
        fdiv f1, f2, f3
        fdiv f1, f4, f5
        nop
        nop
        nop
        fadd f1, f6, f7
        halt
