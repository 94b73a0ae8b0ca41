# machine: os
# Exposed latencies for the debugger golden: the fdiv (4 cycles on the OS) is in flight while
# independent work issues; its result is read only once it has landed.
        .data 0x200
out:    .float 0.0
        .text
start:  { fli f1, 6.0 ; fli f2, 4.0 ; li r1, out ; li r2, 3 }
        { fdiv f3, f1, f2 ; fadd f4, f1, f2 }
        { addi r2, r2, -1 ; fmul f5, f4, f4 }
        { addi r2, r2, -1 ; fsub f6, f5, f4 }
        { addi r2, r2, -1 ; fadd f7, f6, f6 }
        { fadd f8, f3, f7 }
done:   { fsw f8, 0(r1) ; halt }
