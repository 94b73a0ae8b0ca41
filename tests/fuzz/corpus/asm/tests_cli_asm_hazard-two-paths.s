# machine: os
# The read of f1 at the loop's top is reached on two paths with a write still in flight: from
# the prologue (one bundle too short) and around the back edge. Both are reported at once.
        fdiv f1, f2, f3
        li r1, 4
loop:   fadd f2, f1, f1
        addi r1, r1, -1
        { fdiv f1, f2, f3 ; bnez r1, loop }
        halt
