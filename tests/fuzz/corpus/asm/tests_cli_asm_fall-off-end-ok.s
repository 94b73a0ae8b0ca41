# machine: os
        li r1, 1
        { addi r1, r1, 1 ; halt }
