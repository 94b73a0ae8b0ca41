# machine: os
# An operation that is not in the ISA table.
        fmadd f1, f2, f3, f4
        halt
