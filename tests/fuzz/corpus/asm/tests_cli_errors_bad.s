# machine: os
add r1, r2
