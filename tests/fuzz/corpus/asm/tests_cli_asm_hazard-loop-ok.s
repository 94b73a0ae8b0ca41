# machine: os
        li r1, 4
loop:   fadd f2, f1, f1
        { fdiv f1, f2, f3 ; addi r1, r1, -1 }
        nop
        nop
        bnez r1, loop
        halt
