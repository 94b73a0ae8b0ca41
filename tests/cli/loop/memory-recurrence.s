# machine: os
# x[i+1] += x[i]: each pass loads what the previous one stored, a recurrence through memory that
# `nesshi loop` counts in its RecMII (issue 26 item 6).
        .data 0x1000
xs:     .space 256
        .text
        li    r1, xs
        li    r9, 16
loop:
        { lw r5, 0(r1) ; lw r6, 4(r1) }
        { add r5, r5, r6 ; addi r9, r9, -1 }
        { sw r5, 4(r1) ; addi r1, r1, 4 }
        { bnez r9, loop }
        halt
