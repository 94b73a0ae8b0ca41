# machine: os
        addi r127, r1, 1
        halt
