# machine: os
        li r1, 0xffffffff
        li r2, -0x80000000
        halt
        .data 0x100
        .byte 255, -128
