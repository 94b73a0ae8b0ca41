# machine: os
# saxpy_pipelined: y[i] = a * x[i] + y[i] for N floats, software-pipelined on the OS.
# One iteration is load x (t0), load y + multiply (t1), add (t2), store (t3); the kernel
# overlaps the store of iteration i-1 with the loads of iteration i, giving 3 cycles per
# element (II = 3, bounded by the 2 integer units: 2 loads + store + index + branch).
# One index register r1 walks both arrays through absolute offsets (xs(r1), ys(r1)).
        .equ N, 8
        .data 0x1000
xs:     .float 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0
ys:     .float 0.5, 0.5, 0.5, 0.5, -1.0, -1.0, -1.0, -1.0

        .text
        { li r1, 0 ; li r9, 4 * N ; fli f0, 2.5 }
# prologue: iteration 0 up to its add
        flw f1, xs(r1)
        { flw f2, ys(r1) ; addi r1, r1, 4 ; fmul f3, f0, f1 }
        { fadd f4, f3, f2 }
# kernel: store of iteration i-1 | loads, multiply, add of iteration i
loop:   { flw f1, xs(r1) ; fsw f4, ys-4(r1) }
        { flw f2, ys(r1) ; addi r1, r1, 4 ; fmul f3, f0, f1 }
        { fadd f4, f3, f2 ; bne r1, r9, loop }
# epilogue: store of the last iteration
        { fsw f4, ys-4(r1) ; halt }
