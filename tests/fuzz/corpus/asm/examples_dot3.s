# machine: os
# dot3: the dot product of two 3-vectors in SRAM, bundled for the OS (2 IU + 2 FPU).
# Loads and the store issue on the integer units; the FPRF has 2 write ports, so at most two
# float results (loads included) may land per cycle. Result: 1.5*4 - 2*0.5 + 0.25*8 = 7.0.
        .data 0x100
vec_a:  .float 1.5, -2.0, 0.25
vec_b:  .float 4.0, 0.5, 8.0
result: .float 0.0

        .text
        .global start
start:  { li r1, vec_a ; li r2, vec_b }
        { flw f1, 0(r1) ; flw f4, 0(r2) }
        { flw f2, 4(r1) ; fmul f7, f1, f4 }           # a0*b0 while a1 arrives
        { flw f5, 4(r2) ; flw f3, 8(r1) }
        { flw f6, 8(r2) ; fmul f8, f2, f5 }
        { fmul f9, f3, f6 ; fadd f10, f7, f8 ; li r3, result }
        { fadd f10, f10, f9 }
        { fsw f10, 0(r3) ; halt }
