# machine: os
# An endless loop (r2 stays 0), for the interactive debugger test: `continue` runs until Ctrl-C.
        li r1, 0
loop:   { addi r1, r1, 1 ; beqz r2, loop }
        halt
