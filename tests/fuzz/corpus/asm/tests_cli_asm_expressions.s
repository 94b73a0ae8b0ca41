# machine: os
# Expression errors: division by zero and a cyclic .equ.
        .equ A, B + 1
        .equ B, A * 2
        li r1, 10 / (3 - 3)
        li r2, A
        halt
