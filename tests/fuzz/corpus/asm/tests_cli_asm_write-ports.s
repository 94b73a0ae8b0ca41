# machine: os
# Three FPRF results land in cycle +1; the OS FPRF has two write ports (the IC has three).
        { fadd f1, f2, f3 ; fadd f4, f5, f6 ; flw f7, 0(r1) }
        halt
