# machine: os
# Forward references, precedence and the operators.
        .equ SIZE, COUNT * 4
        li r1, SIZE + (1 << 4) - ~0 % 3
        li r2, (0x10 | 0b11) ^ 'A' & 0xff
        li r3, -end >> 1
        .equ COUNT, 12
end:    halt
