# machine: os
# Wrong number of operands.
        add r1, r2
        halt
