# machine: os
# On the taken path the fdiv result is read two cycles after issue.
        { fdiv f1, f2, f3 ; beqz r1, target }
        nop
        nop
        nop
target: fadd f4, f1, f1
        halt
