# machine: os
# Two fdivs land in cycle +4 together with a later one-cycle fadd: three FPRF writes in one
# cycle, but the OS FPRF has two write ports.
        { fdiv f1, f2, f3 ; fdiv f4, f5, f6 }
        nop
        nop
        fadd f7, f8, f9
        halt
