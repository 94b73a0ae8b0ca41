# machine: os
# The fadd writes f1 in the cycle the fdiv lands when the branch falls through, before it when
# the branch is taken: one error, for the path that needs the most padding.
        fdiv f1, f2, f3
        beqz r1, skip
        nop
skip:   fadd f1, f4, f5
        halt
