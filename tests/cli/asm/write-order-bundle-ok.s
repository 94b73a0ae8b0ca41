# machine: os
# The fadd (fpu0) issues first and lands first; the fdiv (fpu1) lands after it.
        { fadd f1, f4, f5 ; fdiv f1, f2, f3 }
        halt
