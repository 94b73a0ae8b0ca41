# machine: os
# A warning, not an error: the last bundle neither halts nor jumps.
        li r1, 1
        addi r1, r1, 1
