# machine: os
# A bundle spread over several lines, with comments and an explicit slot.
        {
            add r1, r2, r3      // first
            iu1: sub r4, r5, r6 # second
            fadd f1, f2, f3
        }
        halt
