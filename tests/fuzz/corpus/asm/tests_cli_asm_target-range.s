# machine: os
# A numeric branch target outside the code.
        jmp 7
        halt
