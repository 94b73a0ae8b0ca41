# machine: seq
# kernels/seq/dda.s: the 3DDDA traversal for the one-unit `seq` machine (models S and M), as a
# careful sequential programmer writes it: branch on the axis, update only that axis. Same
# protocol, state table, padded occupancy map and deferred t_exit test as kernels/os/dda.s (read
# its header for the why); the same float operations in the twin's order, so every VISIT, state
# word and MISS is bit-identical to kernels/twins/dda.hpp.
#
# One voxel step is 9 operations, 9 cycles (paper, sequential: 23):
#   fle c1 = nx <= ny ; beqz c1 -> not_x ; fle c2 = nx <= nz ; beqz c2 -> step_z   (x path)
#   not_x: fle c3 = ny <= nz ; beqz c3 -> step_z                                    (y path)
#   step_k: fmov t_in = n_k ; fadd n_k += delta_k ; add addr += step_k ; lbu occ ; beqz occ -> loop
# (with x <= y and z < x, z < y follows, so "c1 && !c2" goes straight to step_z, exactly the
# twin's choice). No interlocks are needed: every result is used one bundle later at the earliest.
# Setup branches once on "some direction component is zero": the common case (fast_setup) has
# none of the twin's inside/outside selects, which only change results for zero components.
# The straight-line blocks (setup, VISIT, resume) are ordered by `nesshi schedule`, which
# fills the 4-cycle divide latency of the setup with independent work.
# Registers: as kernels/os/dda.s (f10-f12 the three nexts, f16-f18 deltas, r4 voxel address,
# r5-r7 address steps, f9 t_exit, f40 t_in, f41 t_out).
        .include "../abi.inc"
        .text
start:
        { li r0, 0 }
        { li r60, 0x7f800000 }
        { li r61, 0xff800000 }
        { lw r20, GEOM_STRIDE(r0) }
        { lw r21, GEOM_STRIDE+4(r0) }
        { lw r22, GEOM_STRIDE+8(r0) }
        { li r16, OS_OCC }
        { li r17, OS_STATE }
        { li r18, OCC_BORDER }
        { li r19, TAG_RETURN }
        { movif f36, r60 }
        { movif f37, r61 }
        { fli f35, 0.0 }
        { fli f38, 1.0 }
        { flw f20, GEOM_LO(r0) }
        { flw f21, GEOM_LO+4(r0) }
        { flw f22, GEOM_LO+8(r0) }
        { flw f23, GEOM_HI(r0) }
        { flw f24, GEOM_HI+4(r0) }
        { flw f25, GEOM_HI+8(r0) }
        { flw f26, GEOM_CELL(r0) }
        { flw f27, GEOM_CELL+4(r0) }
        { flw f28, GEOM_CELL+8(r0) }
        { flw f29, GEOM_INV_CELL(r0) }
        { flw f30, GEOM_INV_CELL+4(r0) }
        { flw f31, GEOM_INV_CELL+8(r0) }
        { flw f32, GEOM_NMAX(r0) }
        { flw f33, GEOM_NMAX+4(r0) }
        { flw f34, GEOM_NMAX+8(r0) }
        { lw r23, GEOM_OCC0(r0) }
        { sub r24, r0, r20 }
        { sub r25, r0, r21 }
        { sub r26, r0, r22 }

# ---- receive: one tag word tells a new ray from a returning one -----------------------------
next_ray:
        recv r2, CH_IN
        andi r45, r2, TAG_SLOT_MASK
        or r3, r2, r19
        blt r2, r0, resume

# ---- dda_setup, part 1: grid entry and exit (t_in, t_exit) ----------------------------------
new_ray:
        { frecv f1, CH_IN }
        { frecv f2, CH_IN }
        { frecv f3, CH_IN }
        { frecv f4, CH_IN }
        { frecv f5, CH_IN }
        { frecv f6, CH_IN }
        { feq r33, f4, f35 }
        { feq r34, f5, f35 }
        { feq r35, f6, f35 }
        { or r65, r33, r34 }
        { slli r45, r45, OS_STATE_SHIFT }
        { or r65, r65, r35 }
        { add r1, r17, r45 }
        { xor r64, r3, r19 }
        { frecv f7, CH_IN }
        { frecv f8, CH_IN }
        { bnez r65, slow_setup }
# the common case: no direction component is zero, so no selects are needed
fast_setup:
        { fdiv f60, f38, f4 }
        { fdiv f61, f38, f5 }
        { fsub f63, f20, f1 }
        { fdiv f62, f38, f6 }
        nop
        { fsub f66, f23, f1 }
        nop
        { fsub f64, f21, f2 }
        { fsub f67, f24, f2 }
        { fmul f69, f63, f60 }
        { fmul f72, f66, f60 }
        { fsub f65, f22, f3 }
        { fsub f68, f25, f3 }
        { fmul f70, f64, f61 }
        { fmul f73, f67, f61 }
        { fmin f75, f69, f72 }
        { fmax f78, f69, f72 }
        { fmul f71, f65, f62 }
        { fmul f74, f68, f62 }
        { fmin f76, f70, f73 }
        { fmax f79, f70, f73 }
        { fmax f40, f7, f75 }
        { fmin f9, f8, f78 }
        { fmin f77, f71, f74 }
        { fmax f80, f71, f74 }
        { fmax f40, f40, f76 }
        { fmin f9, f9, f79 }
        { fmax f40, f40, f77 }
        { fmin f9, f9, f80 }
        { fle r59, f40, f9 }
        { beqz r59, miss }

# ---- dda_setup, part 2: entry voxel, per-axis next/delta/step, state table --------------------
setup2:
        { fmul f88, f40, f5 }
        { fmul f89, f40, f6 }
        { fadd f91, f2, f88 }
        { fadd f92, f3, f89 }
        { fmul f87, f40, f4 }
        { fsub f94, f91, f21 }
        { fsub f95, f92, f22 }
        { fadd f90, f1, f87 }
        { fmul f97, f94, f30 }
        { fmul f98, f95, f31 }
        { fsub f93, f90, f20 }
        { fmin f97, f33, f97 }
        { fmin f98, f34, f98 }
        { fmul f96, f93, f29 }
        { fmax f97, f35, f97 }
        { fmax f98, f35, f98 }
        { fmin f96, f32, f96 }
        { ftoi r40, f97 }
        { ftoi r41, f98 }
        { fmax f96, f35, f96 }
        { mul r46, r40, r21 }
        { mul r47, r41, r22 }
        { ftoi r39, f96 }
        { add r48, r46, r47 }
        { add r48, r48, r39 }
        { add r4, r48, r23 }
        { lbu r8, 0(r4) }
        { fsw f1, ST_O(r1) }
        { fsw f2, ST_O+4(r1) }
        { fsw f3, ST_O+8(r1) }
        { fsw f4, ST_D(r1) }
        { fsw f5, ST_D+4(r1) }
        { fsw f6, ST_D+8(r1) }
        { fabs f120, f60 }
        { fsw f7, ST_TMIN(r1) }
        { flt r36, f35, f4 }
        { flt r37, f35, f5 }
        { flt r38, f35, f6 }
        { fabs f121, f61 }
        { fmul f123, f26, f120 }
        { fsw f8, ST_TMAX(r1) }
        { add r42, r39, r36 }
        { add r43, r40, r37 }
        { add r44, r41, r38 }
        { fabs f122, f62 }
        { fmul f124, f27, f121 }
        { fsel f16, r33, f36, f123 }
        { fsw f9, ST_TEXIT(r1) }
        { itof f105, r42 }
        { itof f106, r43 }
        { itof f107, r44 }
        { fmul f125, f28, f122 }
        { fsel f17, r34, f36, f124 }
        { fsw f16, ST_DELTA(r1) }
        { fmul f108, f105, f26 }
        { fmul f109, f106, f27 }
        { fmul f110, f107, f28 }
        { fsel f18, r35, f36, f125 }
        { fsw f17, ST_DELTA+4(r1) }
        { fadd f111, f20, f108 }
        { fadd f112, f21, f109 }
        { fadd f113, f22, f110 }
        { sel r5, r36, r20, r24 }
        { fsw f18, ST_DELTA+8(r1) }
        { fsub f114, f111, f1 }
        { fsub f115, f112, f2 }
        { fsub f116, f113, f3 }
        { sel r6, r37, r21, r25 }
        { sw r5, ST_ASTEP(r1) }
        { fmul f117, f114, f60 }
        { fmul f118, f115, f61 }
        { fmul f119, f116, f62 }
        { sel r7, r38, r22, r26 }
        { sw r6, ST_ASTEP+4(r1) }
        { fsel f10, r33, f36, f117 }
        { fsel f11, r34, f36, f118 }
        { fsel f12, r35, f36, f119 }
        { sw r7, ST_ASTEP+8(r1) }
        { bnez r8, visit_setup }

# ---- the voxel-step loop: branch on the axis, update only that axis (9 operations a step) ----
loop:
        fle r9, f10, f11
        beqz r9, not_x
        fle r10, f10, f12
        beqz r10, step_z
step_x:
        fmov f40, f10
        fadd f10, f10, f16
        add r4, r4, r5
        lbu r8, 0(r4)
        beqz r8, loop
        jmp leave
not_x:
        fle r11, f11, f12
        beqz r11, step_z
step_y:
        fmov f40, f11
        fadd f11, f11, f17
        add r4, r4, r6
        lbu r8, 0(r4)
        beqz r8, loop
        jmp leave
step_z:
        fmov f40, f12
        fadd f12, f12, f18
        add r4, r4, r7
        lbu r8, 0(r4)
        beqz r8, loop

# ---- leaving the loop: the frame (left the grid), the deferred t_exit test, or a VISIT --------
leave:
        beq r8, r18, miss
        flt r59, f9, f40
        bnez r59, miss
        fmin f43, f10, f11
        fmin f44, f43, f12
        fmin f41, f44, f9
visit_a:
        { fsw f10, ST_NEXT(r1) }
        { fsw f11, ST_NEXT+4(r1) }
        { fsw f12, ST_NEXT+8(r1) }
        { sub r62, r4, r16 }
        { sw r4, ST_ADDR(r1) }
        { send CH_OS_IC, r3 }
        { send CH_OS_IC, r62 }
        { fsend CH_OS_IC, f40 }
        { fsend CH_OS_IC, f41 }
        { fsend CH_OS_IC, f1 }
        { fsend CH_OS_IC, f2 }
        { fsend CH_OS_IC, f3 }
        { fsend CH_OS_IC, f4 }
        { fsend CH_OS_IC, f5 }
        { fsend CH_OS_IC, f6 }
        { fsend CH_OS_IC, f7 }
        { fsend CH_OS_IC, f8 }
        { fsw f40, ST_TIN(r1) }
        { jmp next_ray }

# ---- the entry voxel is not empty: its exit, then the common VISIT ---------------------------
visit_setup:
        fmin f43, f10, f11
        fmin f44, f43, f12
        fmin f41, f44, f9
        jmp visit_a

# ---- MISS: the ray left the grid, or passed t_exit ------------------------------------------
miss:
        send CH_OS_SC, r64
        jmp next_ray

# ---- RETURN: a ray back from the IC resumes from its saved state ------------------------------
resume:
        { slli r45, r45, OS_STATE_SHIFT }
        { add r1, r17, r45 }
        { xor r64, r3, r19 }
        { flw f10, ST_NEXT(r1) }
        { flw f11, ST_NEXT+4(r1) }
        { flw f12, ST_NEXT+8(r1) }
        { lw r4, ST_ADDR(r1) }
        { lw r5, ST_ASTEP(r1) }
        { lw r6, ST_ASTEP+4(r1) }
        { lw r7, ST_ASTEP+8(r1) }
        { flw f16, ST_DELTA(r1) }
        { flw f17, ST_DELTA+4(r1) }
        { flw f18, ST_DELTA+8(r1) }
        { flw f9, ST_TEXIT(r1) }
        { flw f1, ST_O(r1) }
        { flw f2, ST_O+4(r1) }
        { flw f3, ST_O+8(r1) }
        { flw f4, ST_D(r1) }
        { flw f5, ST_D+4(r1) }
        { flw f6, ST_D+8(r1) }
        { flw f7, ST_TMIN(r1) }
        { flw f8, ST_TMAX(r1) }
        { jmp loop }

# ---- a direction component is zero: the twin's selects (inside ? -inf : +inf) ----------------
slow_setup:
        { fdiv f60, f38, f4 }
        { fdiv f61, f38, f5 }
        { fdiv f62, f38, f6 }
        { fle r50, f20, f1 }
        { fle r53, f1, f23 }
        { fle r51, f21, f2 }
        { fsub f63, f20, f1 }
        { fsub f66, f23, f1 }
        { fle r54, f2, f24 }
        { and r56, r50, r53 }
        { fsub f64, f21, f2 }
        { fsub f67, f24, f2 }
        { fle r52, f22, f3 }
        { fle r55, f3, f25 }
        { and r57, r51, r54 }
        { fsel f81, r56, f37, f36 }
        { fmul f69, f63, f60 }
        { fmul f72, f66, f60 }
        { fsub f65, f22, f3 }
        { fsub f68, f25, f3 }
        { and r58, r52, r55 }
        { fsel f82, r57, f37, f36 }
        { fneg f84, f81 }
        { fmul f70, f64, f61 }
        { fmul f73, f67, f61 }
        { fmin f75, f69, f72 }
        { fmax f78, f69, f72 }
        { fsel f83, r58, f37, f36 }
        { fneg f85, f82 }
        { fmul f71, f65, f62 }
        { fmul f74, f68, f62 }
        { fmin f76, f70, f73 }
        { fmax f79, f70, f73 }
        { fsel f75, r33, f81, f75 }
        { fsel f78, r33, f84, f78 }
        { fneg f86, f83 }
        { fmin f77, f71, f74 }
        { fmax f80, f71, f74 }
        { fsel f76, r34, f82, f76 }
        { fsel f79, r34, f85, f79 }
        { fmax f40, f7, f75 }
        { fmin f9, f8, f78 }
        { fsel f77, r35, f83, f77 }
        { fsel f80, r35, f86, f80 }
        { fmax f40, f40, f76 }
        { fmin f9, f9, f79 }
        { fmax f40, f40, f77 }
        { fmin f9, f9, f80 }
        { fle r59, f40, f9 }
        { beqz r59, miss }
        jmp setup2
