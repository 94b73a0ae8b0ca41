# machine: ic
# cross3_ic: the cross product of two 3-vectors on the IC (1 IU + 3 FPU; FPRF 7 read / 3 write
# ports). The single integer unit serialises the six loads; each later bundle overlaps one load
# with up to two multiplies, then three multiplies and three subtracts run side by side.
# a = (1, 2, 3), b = (4, 5, 6): a x b = (-3, 6, -3), stored at `out`.
        .data 0x400000
vecs:   .float 1.0, 2.0, 3.0          # a
        .float 4.0, 5.0, 6.0          # b
out:    .float 0.0, 0.0, 0.0

        .text
        li r1, vecs
        flw f0, 0(r1)                 # a0
        flw f1, 4(r1)                 # a1
        flw f2, 8(r1)                 # a2
        flw f3, 12(r1)                # b0
        { flw f4, 16(r1) ; fmul f10, f2, f3 }                   # b1 | a2*b0
        { flw f5, 20(r1) ; fmul f6, f1, f3 ; fmul f7, f0, f4 }  # b2 | a1*b0, a0*b1
        { li r3, out ; fmul f8, f1, f5 ; fmul f9, f2, f4 ; fmul f11, f0, f5 }
        { fsub f12, f8, f9 ; fsub f13, f10, f11 ; fsub f14, f7, f6 }
        fsw f12, 0(r3)
        fsw f13, 4(r3)
        { fsw f14, 8(r3) ; halt }
