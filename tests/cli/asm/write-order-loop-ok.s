# machine: os
# The fdiv at the top of the next iteration lands one cycle after the one at the bottom, still
# in flight around the back edge.
        li r1, 4
loop:   fdiv f1, f4, f5
        addi r1, r1, -1
        { fdiv f1, f2, f3 ; bnez r1, loop }
        halt
