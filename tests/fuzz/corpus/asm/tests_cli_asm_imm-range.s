# machine: os
# Immediates must fit 32 bits (signed or unsigned); .byte values 8 bits.
        li r1, 0x100000000
        halt
        .data 0x100
        .byte 256
