# machine: os
# A dynamic write-port conflict on a taken branch path the assembler cannot follow (an indirect
# jump): the fdiv (latency 4) issued in cycle 1 lands in cycle 5, together with the two float
# writes of the bundle at `target` (issued in cycle 4): three FPRF writes in one cycle, and the
# OS has two write ports. The checked engine stops with a report; the fast engine trusts the code.
# Our assembler rejects this file (its flow analysis assumes jr may reach any label), so the
# object beside it, port_conflict_branch.o, is built by tests/iss/fault_test.cpp (same bundles,
# same line numbers); NESSHI_UPDATE_GOLDEN=1 rewrites it.
        { fli f2, 6.0 ; fli f3, 2.0 ; li r5, target }
        { fdiv f9, f2, f3 }
        nop
        jr r5
        halt
target: { fadd f1, f2, f3 ; fmul f4, f2, f3 }
        halt
