# machine: os
# Padded on the taken path too: the fadd lands after the fdiv whichever way the branch goes.
        fdiv f1, f2, f3
        beqz r1, skip
        nop
skip:   nop
        nop
        fadd f1, f4, f5
        halt
