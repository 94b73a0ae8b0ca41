# machine: seq
# kernels/seq/intersect.s: the IC intersection kernel for the one-unit `seq` machine (models S
# and M), written as a careful sequential programmer would: one primitive at a time, with early
# exits as soon as a test fails (back face, t outside (tmin, bound), a < 0, b < 0, a + b > 1;
# quadrics: negative discriminant, root out of range). Same float operations, in the twins'
# order, as kernels/ic/intersect.s, so the results are bit-identical; only the control differs.
# The straight-line pieces between branches are ordered by `nesshi schedule` (it fills the
# divide and square-root latencies with independent work).
# Protocol, memory layout and dispatch codes: kernels/abi.hpp.
# Registers: f1-f3 o, f4-f6 d, f7 tmin, f8 tmax, f9 t_out, f10 bound (= best t so far),
#   f13 f14 best u, v, f21 +inf, f23 0, f24 1; r1 list pointer, r2 tag, r10 record, r24 best
#   record (0: none), r25 best front, r20 voxel table.
        .include "../abi.inc"
        .text
start:
        { li r0, 0 }
        { li r62, tri1 }
        { lw r20, IC_HEADER+ICH_VOXTAB(r0) }
        { sw r62, IC_JUMPS_A+CODE_TRI1(r0) }
        { li r62, tri2 }
        { sw r62, IC_JUMPS_A+CODE_TRI2(r0) }
        { li r62, quad1 }
        { sw r62, IC_JUMPS_A+CODE_QUAD1(r0) }
        { li r62, quad2 }
        { sw r62, IC_JUMPS_A+CODE_QUAD2(r0) }
        { li r62, done }
        { sw r62, IC_JUMPS_A+CODE_END(r0) }
        { li r62, sph1 }
        { sw r62, IC_JUMPS_A+CODE_SPH1(r0) }
        { li r62, sph2 }
        { li r60, 0x7f800000 }
        { sw r62, IC_JUMPS_A+CODE_SPH2(r0) }
        { li r62, ball1 }
        { movif f21, r60 }
        { fli f23, 0.0 }
        { fli f24, 1.0 }
        { sw r62, IC_JUMPS_A+CODE_BALL1(r0) }

# ---- receive a VISIT ----------------------------------------------------------------------------
next_ray:
        { recv r2, CH_IN }
        { recv r3, CH_IN }
        { frecv f25, CH_IN }
        { frecv f9, CH_IN }
        { movfi r7, f9 }
        { addi r7, r7, 1 }
        { frecv f1, CH_IN }
        { frecv f2, CH_IN }
        { frecv f3, CH_IN }
        { frecv f4, CH_IN }
        { frecv f5, CH_IN }
        { frecv f6, CH_IN }
        { frecv f7, CH_IN }
        { frecv f8, CH_IN }
        { slli r5, r3, 2 }
        { andi r6, r2, TAG_KIND_MASK << TAG_KIND_SHIFT }
        { movif f26, r7 }
        { add r5, r5, r20 }
        { addi r6, r6, -(KIND_SHADOW << TAG_KIND_SHIFT) }
        { fmin f27, f26, f8 }
        { lw r1, 0(r5) }
        { fsel f10, r6, f27, f8 }
        { li r24, 0 }

# ---- next primitive: dispatch on the record's code -----------------------------------------------
next_prim:
        { lw r10, 0(r1) }
        { lw r14, REC_CODE(r10) }
        { lw r13, IC_JUMPS_A(r14) }
        { addi r1, r1, 4 }
        { jr r13 }

# ---- triangle, one-sided / two-sided ---------------------------------------------------------------
tri1:
        { flw f30, REC_W+0(r10) }
        { flw f31, REC_W+4(r10) }
        { flw f32, REC_W+8(r10) }
        { fmul f71, f30, f4 }
        { fmul f72, f31, f5 }
        { fmul f73, f32, f6 }
        { fadd f74, f71, f72 }
        { fadd f75, f74, f73 }
        { flt r30, f75, f23 }
        { beqz r30, next_prim }
        jmp tri_common
tri2:
        { flw f30, REC_W+0(r10) }
        { flw f31, REC_W+4(r10) }
        { flw f32, REC_W+8(r10) }
        { fmul f71, f30, f4 }
        { fmul f72, f31, f5 }
        { fmul f73, f32, f6 }
        { fadd f74, f71, f72 }
        { fadd f75, f74, f73 }
        { feq r30, f75, f23 }
        { bnez r30, next_prim }
tri_common:
        { fmul f76, f30, f1 }
        { fmul f77, f31, f2 }
        { fmul f78, f32, f3 }
        { fadd f79, f76, f77 }
        { flw f33, REC_W+12(r10) }
        { fadd f80, f79, f78 }
        { fadd f81, f80, f33 }
        { fneg f82, f81 }
        { fdiv f83, f82, f75 }
        { flw f34, REC_W+16(r10) }
        { flw f35, REC_W+20(r10) }
        nop
        { flt r31, f7, f83 }
        { flw f36, REC_W+24(r10) }
        { beqz r31, next_prim }
        { flt r31, f83, f10 }
        { beqz r31, next_prim }
        { fmul f84, f83, f4 }
        { fmul f86, f83, f5 }
        { fadd f85, f1, f84 }
        { fadd f87, f2, f86 }
        { fmul f88, f83, f6 }
        { fadd f89, f3, f88 }
        { fmul f90, f34, f85 }
        { fmul f91, f35, f87 }
        { fadd f93, f90, f91 }
        { fmul f92, f36, f89 }
        { flw f37, REC_W+28(r10) }
        { fadd f94, f93, f92 }
        { fadd f17, f94, f37 }
        { fle r32, f23, f17 }
        { beqz r32, next_prim }
        { flw f38, REC_W+32(r10) }
        { flw f39, REC_W+36(r10) }
        { flw f40, REC_W+40(r10) }
        { fmul f95, f38, f85 }
        { fmul f96, f39, f87 }
        { fadd f98, f95, f96 }
        { fmul f97, f40, f89 }
        { flw f41, REC_W+44(r10) }
        { fadd f99, f98, f97 }
        { fadd f18, f99, f41 }
        { fle r32, f23, f18 }
        { beqz r32, next_prim }
        { fadd f100, f17, f18 }
        { fle r33, f100, f24 }
        { beqz r33, next_prim }
        { fmov f10, f83 }
        { mov r24, r10 }
        { fmov f13, f17 }
        { fmov f14, f18 }
        { li r25, 1 }
        { jmp next_prim }

# ---- quadric, one-sided / two-sided: common part up to the discriminant -----------------------------
quad1:
        { li r26, 0 }
        { li r27, 0 }
        { jmp quad_common }
quad2:
        { li r26, 1 }
        { li r27, 0 }
        { jmp quad_common }
sph1:
        { li r26, 0 }
        { li r27, 1 }
        { jmp quad_common }
sph2:
        { li r26, 1 }
        { li r27, 1 }
        { jmp quad_common }
quad_common:
        { flw f30, REC_W+0(r10) }
        { flw f31, REC_W+4(r10) }
        { flw f32, REC_W+8(r10) }
        { fsub f71, f1, f30 }
        { fsub f72, f2, f31 }
        { fsub f73, f3, f32 }
        { fmul f74, f71, f4 }
        { fmul f75, f72, f5 }
        { fmul f76, f73, f6 }
        { fadd f77, f74, f75 }
        { fadd f78, f77, f76 }
        { fneg f79, f78 }
        { fmul f80, f79, f4 }
        { fmul f82, f79, f5 }
        { fadd f81, f71, f80 }
        { fadd f83, f72, f82 }
        { fmul f84, f79, f6 }
        { flw f33, REC_W+12(r10) }
        { flw f34, REC_W+16(r10) }
        { flw f36, REC_W+24(r10) }
        { fadd f85, f73, f84 }
        { flw f37, REC_W+28(r10) }
        { flw f38, REC_W+32(r10) }
        { fmul f101, f33, f81 }
        { fmul f102, f36, f83 }
        { fmul f107, f36, f81 }
        { fmul f108, f34, f83 }
        { flw f35, REC_W+20(r10) }
        { fadd f103, f101, f102 }
        { fmul f104, f38, f85 }
        { fadd f109, f107, f108 }
        { fmul f110, f37, f85 }
        { fmul f113, f38, f81 }
        { fmul f114, f37, f83 }
        { flw f39, REC_W+36(r10) }
        { flw f40, REC_W+40(r10) }
        { fadd f105, f103, f104 }
        { fadd f111, f109, f110 }
        { fadd f115, f113, f114 }
        { fmul f116, f35, f85 }
        { flw f41, REC_W+44(r10) }
        { fmul f86, f33, f4 }
        { fmul f87, f36, f5 }
        { fmul f91, f36, f4 }
        { fmul f92, f34, f5 }
        { fadd f106, f105, f39 }
        { fadd f112, f111, f40 }
        { fadd f117, f115, f116 }
        { fadd f88, f86, f87 }
        { fmul f89, f38, f6 }
        { fadd f93, f91, f92 }
        { fmul f94, f37, f6 }
        { fmul f96, f38, f4 }
        { fmul f97, f37, f5 }
        { fadd f118, f117, f41 }
        { fmul f60, f81, f106 }
        { fmul f61, f83, f112 }
        { fmul f65, f39, f81 }
        { fmul f66, f40, f83 }
        { fadd f90, f88, f89 }
        { fadd f95, f93, f94 }
        { fadd f98, f96, f97 }
        { fmul f99, f35, f6 }
        { fadd f62, f60, f61 }
        { fmul f63, f85, f118 }
        { fadd f67, f65, f66 }
        { fmul f68, f41, f85 }
        { fadd f100, f98, f99 }
        { fmul f50, f4, f90 }
        { fmul f51, f5, f95 }
        { fmul f55, f4, f106 }
        { fmul f56, f5, f112 }
        { fadd f64, f62, f63 }
        { fadd f69, f67, f68 }
        { flw f42, REC_W+48(r10) }
        { fadd f52, f50, f51 }
        { fmul f53, f6, f100 }
        { fadd f57, f55, f56 }
        { fmul f58, f6, f118 }
        { fadd f70, f64, f69 }
        { fadd f54, f52, f53 }
        { fadd f59, f57, f58 }
        { fadd f119, f70, f42 }
        { fmul f120, f59, f59 }
        { fmul f121, f54, f119 }
        { fsub f122, f120, f121 }
        { fle r30, f23, f122 }
        { beqz r30, next_prim }
quad_roots:
        { fsqrt f123, f122 }
        { fneg f124, f59 }
        nop
        nop
        { fsub f125, f124, f123 }
        { fdiv f126, f125, f54 }
        nop
        nop
        nop
        { fadd f127, f79, f126 }
        { bnez r27, sph_root }
# the axial clip (cylinders, cones)
        { flw f43, REC_W+52(r10) }
        { flw f44, REC_W+56(r10) }
        { flw f45, REC_W+60(r10) }
        { fmul f56, f43, f4 }
        { fmul f57, f44, f5 }
        { fmul f50, f43, f81 }
        { fmul f51, f44, f83 }
        { fadd f58, f56, f57 }
        { fmul f60, f45, f6 }
        { fadd f52, f50, f51 }
        { fmul f53, f45, f85 }
        { fadd f61, f58, f60 }
        { fadd f55, f52, f53 }
        { fmul f62, f126, f61 }
        { flw f46, REC_W+64(r10) }
        { fadd f63, f55, f62 }
        { bnez r26, quad_two }
# one-sided: only the front root
        { flt r31, f7, f127 }
        { beqz r31, next_prim }
        { flt r31, f127, f10 }
        { beqz r31, next_prim }
        { fle r32, f23, f63 }
        { beqz r32, next_prim }
        { fle r32, f63, f46 }
        { beqz r32, next_prim }
        { fmov f10, f127 }
        { mov r24, r10 }
        { li r25, 1 }
        { jmp next_prim }
# two-sided: the nearer valid root
quad_two:
        { fadd f65, f124, f123 }
        { fdiv f66, f65, f54 }
        { flt r31, f7, f127 }
        { fsel f70, r31, f127, f21 }
        { fle r32, f23, f63 }
        { fadd f67, f79, f66 }
        { fmul f68, f66, f61 }
        { fadd f69, f55, f68 }
        { flt r34, f7, f67 }
        { fsel f71, r34, f67, f21 }
        { fle r35, f23, f69 }
        { fsel f70, r32, f70, f21 }
        { fle r33, f63, f46 }
        { fsel f71, r35, f71, f21 }
        { fle r36, f69, f46 }
        { fsel f70, r33, f70, f21 }
        { fsel f71, r36, f71, f21 }
        { fmin f72, f71, f70 }
        { flt r38, f72, f10 }
        { fle r37, f70, f71 }
        { beqz r38, next_prim }
        { fmov f10, f72 }
        { mov r24, r10 }
        { mov r25, r37 }
        { jmp next_prim }

# spheres (no axial clip, see kernels/image.hpp): the root's range only
sph_root:
        bnez r26, sph_two
        { flt r31, f7, f127 }
        { beqz r31, next_prim }
        { flt r31, f127, f10 }
        { beqz r31, next_prim }
        { fmov f10, f127 }
        { mov r24, r10 }
        { li r25, 1 }
        { jmp next_prim }
sph_two:
        { fadd f65, f124, f123 }
        { fdiv f66, f65, f54 }
        { flt r31, f7, f127 }
        { fsel f70, r31, f127, f21 }
        nop
        { fadd f67, f79, f66 }
        { flt r34, f7, f67 }
        { fsel f71, r34, f67, f21 }
        { fmin f72, f71, f70 }
        { flt r38, f72, f10 }
        { fle r37, f70, f71 }
        { beqz r38, next_prim }
        { fmov f10, f72 }
        { mov r24, r10 }
        { mov r25, r37 }
        { jmp next_prim }

# plain sphere (M = I, g = 0, one-sided; exact, see kernels/image.hpp): no matrix products
ball1:
        { flw f30, REC_W+0(r10) }
        { flw f31, REC_W+4(r10) }
        { flw f32, REC_W+8(r10) }
        { fsub f71, f1, f30 }
        { fsub f72, f2, f31 }
        { fsub f73, f3, f32 }
        { fmul f74, f71, f4 }
        { fmul f75, f72, f5 }
        { fadd f77, f74, f75 }
        { fmul f76, f73, f6 }
        { fadd f78, f77, f76 }
        { fneg f79, f78 }
        { fmul f80, f79, f4 }
        { fmul f82, f79, f5 }
        { fadd f81, f71, f80 }
        { fadd f83, f72, f82 }
        { fmul f84, f79, f6 }
        { fadd f85, f73, f84 }
        { fmul f60, f81, f81 }
        { fmul f61, f83, f83 }
        { fmul f50, f4, f4 }
        { fmul f51, f5, f5 }
        { fmul f55, f4, f81 }
        { fmul f56, f5, f83 }
        { fadd f62, f60, f61 }
        { fmul f63, f85, f85 }
        { flw f42, REC_W+48(r10) }
        { fadd f52, f50, f51 }
        { fmul f53, f6, f6 }
        { fadd f57, f55, f56 }
        { fmul f58, f6, f85 }
        { fadd f64, f62, f63 }
        { fadd f54, f52, f53 }
        { fadd f59, f57, f58 }
        { fadd f119, f64, f42 }
        { fmul f120, f59, f59 }
        { fmul f121, f54, f119 }
        { fsub f122, f120, f121 }
        { fle r30, f23, f122 }
        { li r26, 0 }
        { li r27, 1 }
        { beqz r30, next_prim }
        jmp quad_roots

# ---- end of the list: HIT or RETURN ---------------------------------------------------------------
done:
        bnez r24, hit
return:
        { send CH_IC_OS, r2 }
        { jmp next_ray }
hit:
        { lw r15, REC_CODE(r24) }
        { li r8, 0x7fffffff }
        { slti r16, r15, CODE_QUAD1 }
        { and r8, r2, r8 }
        { lw r9, REC_INDEX(r24) }
        { fsel f13, r16, f13, f23 }
        { fsel f14, r16, f14, f23 }
        { send CH_IC_SC, r8 }
        { send CH_IC_SC, r9 }
        { fsend CH_IC_SC, f10 }
        { fsend CH_IC_SC, f13 }
        { fsend CH_IC_SC, f14 }
        { send CH_IC_SC, r25 }
        { jmp next_ray }
