# machine: os
# The same label defined twice.
top:    add r1, r2, r3
top:    halt
