# machine: os
# Four cycles separate the fdiv from the read on both the taken and the fall-through path.
        fdiv f1, f2, f3
        nop
        nop
        { nop ; beqz r1, target }
        nop
target: fadd f4, f1, f1
        halt
