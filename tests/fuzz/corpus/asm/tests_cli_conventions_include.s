# machine: os
# Needs -I inc: an option value before the positional argument must not swallow it.
        .include "k.inc"
        li r1, K
        halt
