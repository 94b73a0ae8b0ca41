# machine: os
# Register numbers beyond the file (128 registers per file on os).
        addi r128, r1, 1
        halt
