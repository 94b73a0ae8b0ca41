# machine: os
        jmp 1
        halt
