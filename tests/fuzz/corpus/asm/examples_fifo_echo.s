# machine: os
# fifo_echo: receives a count n on channel IN, then n words; sends each word plus one on
# channel OUT. Shows FIFO receive/send and a two-bundle loop with the branch beside the send.
        .equ IN, 0
        .equ OUT, 1
        recv r1, IN
        beqz r1, done
loop:   recv r2, IN
        { addi r2, r2, 1 ; addi r1, r1, -1 }
        { send OUT, r2 ; bnez r1, loop }
done:   halt
