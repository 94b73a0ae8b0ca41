# machine: os
# Two selects read six IRF registers; the OS IRF has five read ports.
        { sel r1, r2, r3, r4 ; sel r5, r6, r7, r8 }
        halt
