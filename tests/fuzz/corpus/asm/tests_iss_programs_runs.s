# machine: os-real
# Runs of plain bundles for the engine tests: a FIFO bundle opening a run, results of latency 2,
# 3 and 12 landing inside runs and across calls, loads and stores, a jal/jr call and a loop
# branch with os-real's branch bubble.
        .data 0x1000
buf:    .word 7, 9, 11, 13, 0, 0
        .text
        { li r10, buf ; li r9, 6 ; fli f1, 1.5 ; fli f2, 2.25 }
        { fli f3, 0.5 ; li r5, 0 }
        nop
        nop
loop:   { recv r1, 0 ; fmul f4, f1, f2 ; fadd f5, f2, f3 }
        { lw r2, 0(r10) ; fdiv f6, f2, f3 ; addi r9, r9, -1 }
        { xor r3, r1, r9 ; lw r6, 4(r10) }
        { fadd f7, f4, f5 ; add r4, r2, r3 }
        { sw r4, 8(r10) ; add r5, r5, r6 ; fmul f8, f1, f1 }
        { jal r31, sub }
        nop
        { fmul f9, f7, f8 ; lw r7, 8(r10) }
        nop
        nop
        { add r5, r5, r7 ; fadd f10, f9, f8 }
        nop
        nop
        nop
        { send 1, r5 ; fadd f12, f6, f10 ; bnez r9, loop }
        halt
sub:    { addi r11, r11, 3 ; fadd f11, f3, f3 }
        { sw r11, 12(r10) }
        nop
        { jr r31 }
