# machine: os
# Around the back edge, the fdiv at the bottom of the loop is still in flight when the fadd at
# the top of the next iteration writes f1.
        li r1, 4
loop:   fadd f1, f4, f5
        addi r1, r1, -1
        { fdiv f1, f2, f3 ; bnez r1, loop }
        halt
