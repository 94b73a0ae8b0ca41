# machine: seq
# sum_seq: sums an array of N words on the sequential processor (one op per bundle) and stores
# the total (31) at `total`. The loop counts down and branches back while the count is nonzero.
        .equ N, 8
        .data 0x200
array:  .word 3, 1, 4, 1, 5, 9, 2, 6
total:  .word 0

        .text
        li r1, array
        li r2, N
        li r3, 0
loop:   lw r4, 0(r1)
        add r3, r3, r4
        addi r1, r1, 4
        addi r2, r2, -1
        bnez r2, loop
        li r5, total
        sw r3, 0(r5)
        halt
