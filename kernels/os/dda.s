# machine: os
# kernels/os/dda.s: the OS processor's 3DDDA traversal (Amanatides-Woo / Snyder-Barr), the
# operation order of the native twin kernels/twins/dda.hpp, software-pipelined to 5 cycles per voxel
# step (the paper: 11). Protocol, record layouts and memory map: kernels/abi.hpp.
#
# Generated: the straight-line blocks (setup, VISIT, resume) are list-scheduled from dda.pk by
# `nesshi schedule`; the loop and the leave paths are scheduled by hand and copied verbatim.
#
# What a ray does here
#   NEW ray (9 words)   dda_setup: grid entry t_in and exit t_exit, entry voxel, per-axis
#                       next/delta/address step; the state goes to the slot's SRAM state entry.
#   voxel loop          one step per voxel until the occupancy byte of the new voxel is non-zero.
#   leave               OCC_BORDER (the frame around the grid): MISS to the SC. Otherwise the
#                       deferred t_exit test (below), then VISIT (12 words) to the IC.
#   RETURN (1 word)     the IC found no hit: reload the state from SRAM and step on.
#
# Two algorithmic changes make the loop short (neither changes any result):
#   1. A padded occupancy map: a one-voxel frame of OCC_BORDER bytes around the grid. Leaving the
#      grid along axis k (the twin's i[k] == end[k]) lands on a frame byte, so the occupancy load
#      that the loop needs anyway also detects the exit: no per-axis index, end value or compare.
#   2. A deferred t_exit test. The twin stops as soon as the chosen next_k > t_exit. The chosen
#      next (= the new voxel's t_in) never decreases along the walk (delta >= 0, no NaN: see the
#      ABI's direction rule), so "some step so far had t_in > t_exit" equals "the current t_in >
#      t_exit". The loop therefore tests t_exit only when it leaves for a non-empty voxel, where
#      it decides MISS or VISIT exactly as the twin would. (Cost: a ray whose tmax ends inside the
#      grid walks on through empty voxels until the next non-empty one or the frame.)
#
# One voxel step, from the state P (nx, ny, nz) to the state Q (twin: k = argmin with x before y
# before z on ties; next_k += delta_k; address += step_k):
#   c1 = nx <= ny   c2 = nx <= nz   c3 = ny <= nz                 (fle, FPU, write the IRF)
#   kx = c1 & c2    (x advances)    nkz = c2 | c3 (z does not advance)
#   y advances iff !c1 & c3 (with no NaN, equal to the twin's !kx & c3), so
#   Qx = kx ? Px + dx : Px          Qy = c1 ? Py : (c3 ? Py + dy : Py)     Qz = nkz ? Pz : Pz + dz
#   address += kx ? ax : (c3 ? ay : az);  occ = byte[address];  leave if occ != 0
# The three sums are computed speculatively; fsel keeps exactly the twin's bits (an axis that
# does not advance keeps its register unchanged).
#
# Resources per step: FPU 10 (3 fle, 3 fadd, 4 fsel) of 2 x 5 = 10 slots; IU 7 (and, or, 2 sel,
# add, lbu, bnez) of 10; IRF writes 9 of 2 x 5 = 10 (compares write the IRF too); IRF reads
# 18 of 25; FPRF writes 7 of 10, reads 20 of 25.
#   ResMII = max(FPU 10/2, IU 7/2, IRF-write 9/2, ...) = 5.    RecMII = 3 (next -> fle -> and ->
#   fsel -> next). II = 5 = ResMII: the loop is resource-bound (FPU slots, IRF write ports).
#
# Modulo reservation table of one step (issue cycle @0..@6; II = 5, so @5/@6 overlap @0/@1 of
# the next step). Columns: the two IUs, the two FPUs.
#   @0 |                           |                    | fle c1,Px,Py       |
#   @1 |                           |                    | fle c2,Px,Pz       | fle c3,Py,Pz
#   @2 | and kx,c1,c2              | sel tmp,c3,ay,az   | fadd sx,Px,dx      | fadd sy,Py,dy
#   @3 | sel astep,kx,ax,tmp       |                    | fsel u,c3,sy,Py    | fsel Qx,kx,sx,Px
#   @4 | add addr,addr,astep       | or nkz,c2,c3       | fsel Qy,c1,Py,u    | fadd sz,Pz,dz
#   @5 | lbu occ,0(addr)           |                    | fsel Qz,nkz,Pz,sz  |
#   @6 | bnez occ,leave            |                    |                    |
# Modulo view (cycle mod 5): slot use IU 2/1/2/1/1 (+ the back-edge jmp), FPU 2/2/2/2/2.
# Why each op sits where it does:
#   - @0 holds only fle c1 (reads Px, Py): the previous step writes Pz at its @5 = this @0, so
#     the compares that read z (c2, c3) wait until @1. That frees an IRF write port in @0 for the
#     previous step's lbu (its @5).
#   - kx needs c1 and c2 (@2); tmp needs c3 (@2); astep both (@3); the address chain add -> lbu ->
#     bnez then ends at @6, one cycle into the next step: the only cross-iteration overlap.
#   - fsel Qx at @3 is the first use of kx; Qy goes through u so that no IRF flag "ky" is needed
#     (one IRF write fewer: 9 instead of 10 per step) at the cost of one FPU op (10 of 10).
#   - IRF read ports are the tightest per bundle: @2 reads 5 (and 2, sel 3), @3 5 (sel 3, two
#     fsel flags), @4 5 (add 2, or 2, fsel flag 1). Moving nkz to @3 would need 6.
# Loop-carried dependences: P -> Q (distance 1, through fle/and/fsel: length 3 <= II); addr ->
# addr (add, length 1). Everything else is recomputed each step.
#
# Unrolled by two (modulo variable expansion): step a reads A = f10-f12 and writes B = f13-f15,
# step b the reverse. A leave after step a still has the old nexts (A) and the step's kx and nkz
# (overwritten only at the next step's @2/@4, after its @6 branch), so the voxel's t_in is
# recovered exactly as the twin chose it: t_in = kx ? Ax : (nkz ? Ay : Az).
# Loop body = 10 bundles (2 steps), rotated so that its last bundle carries the back-edge jmp:
#   loop+0  a@1 | b@6 (bnez -> leave_b)     loop+5  a@6 (bnez -> leave_a) | b@1
#   loop+1  a@2                             loop+6  b@2
#   loop+2  a@3                             loop+7  b@3
#   loop+3  a@4                             loop+8  b@4
#   loop+4  a@5 | b@0                       loop+9  b@5 | a@0 (next pair) | jmp loop
# Entry (enter_loop, resume): a@0 plus occ = 0, so the b@6 test of the first bundle falls through.
#
# Register allocation
#   r0 0            r1 state entry of the slot   r2 tag   r3 tag|TAG_RETURN   r64 tag for MISS
#   r4 voxel address (OS_OCC + padded index)     r5-r7 ax ay az (signed padded strides)
#   r8 occ          r9-r11 c1 c2 c3   r12 kx   r13 tmp   r14 astep   r15 nkz
#   r16 OS_OCC      r17 OS_STATE   r18 OCC_BORDER   r19 TAG_RETURN   r20-r26 strides, occ0, -strides
#   f1-f3 o   f4-f6 d   f7 tmin   f8 tmax   f9 t_exit   f10-f12 next A   f13-f15 next B
#   f16-f18 delta   f19 f50 f51 sx sy sz   f52 u   f20-f38 grid geometry and constants
#   f40 t_in   f41 t_out (voxel exit = min(min(min(nx, ny), nz), t_exit), the twin's voxel_exit)
#   setup temporaries r30-r63, f60-f125.
        .include "../abi.inc"
        .text
start:
        { li r0, 0 ; li r16, OS_OCC ; fli f35, 0.0 ; fli f38, 1.0 }
        { li r17, OS_STATE ; li r18, OCC_BORDER }
        { li r19, TAG_RETURN ; li r60, 0x7f800000 }
        { li r61, 0xff800000 ; movif f36, r60 ; flw f20, GEOM_LO(r0) }
        { flw f21, GEOM_LO+4(r0) ; flw f22, GEOM_LO+8(r0) }
        { flw f23, GEOM_HI(r0) ; flw f24, GEOM_HI+4(r0) }
        { flw f25, GEOM_HI+8(r0) ; flw f26, GEOM_CELL(r0) }
        { flw f27, GEOM_CELL+4(r0) ; flw f28, GEOM_CELL+8(r0) }
        { flw f29, GEOM_INV_CELL(r0) ; flw f30, GEOM_INV_CELL+4(r0) }
        { flw f31, GEOM_INV_CELL+8(r0) ; flw f32, GEOM_NMAX(r0) }
        { flw f33, GEOM_NMAX+4(r0) ; flw f34, GEOM_NMAX+8(r0) }
        { movif f37, r61 ; lw r20, GEOM_STRIDE(r0) ; lw r21, GEOM_STRIDE+4(r0) }
        { lw r22, GEOM_STRIDE+8(r0) ; lw r23, GEOM_OCC0(r0) }
        { sub r24, r0, r20 ; sub r25, r0, r21 }
        { sub r26, r0, r22 }

# ---- receive: one tag word tells a new ray from a returning one -----------------------------
next_ray:
        recv r2, CH_IN
        { blt r2, r0, resume ; andi r45, r2, TAG_SLOT_MASK }

# ---- dda_setup, part 1: grid entry and exit (t_in, t_exit) ----------------------------------
new_ray:
        { iu0: slli r45, r45, OS_STATE_SHIFT ; iu1: or r3, r2, r19 ; fpu0: frecv f1, CH_IN ; fpu1: frecv f2, CH_IN }
        { iu0: frecv f3, CH_IN ; iu1: frecv f4, CH_IN ; fpu0: fle r50, f20, f1 ; fpu1: fle r53, f1, f23 }
        { iu0: frecv f5, CH_IN ; iu1: and r56, r50, r53 ; fpu0: fdiv f60, f38, f4 ; fpu1: fsub f63, f20, f1 }
        { iu0: add r1, r17, r45 ; iu1: frecv f6, CH_IN ; fpu0: fdiv f61, f38, f5 ; fpu1: fsub f66, f23, f1 }
        { iu0: xor r64, r3, r19 ; iu1: frecv f7, CH_IN ; fpu0: fdiv f62, f38, f6 ; fpu1: fle r51, f21, f2 }
        { fsub f64, f21, f2 ; fle r54, f2, f24 }
        { fsub f67, f24, f2 ; fle r52, f22, f3 ; and r57, r51, r54 }
        { fle r55, f3, f25 ; fsel f81, r56, f37, f36 }
        { and r58, r52, r55 ; fmul f69, f63, f60 ; fmul f72, f66, f60 }
        { iu0: frecv f8, CH_IN ; fpu0: feq r33, f4, f35 ; fpu1: fsub f65, f22, f3 }
        { fsub f68, f25, f3 ; fsel f82, r57, f37, f36 }
        { fneg f84, f81 ; fmul f70, f64, f61 }
        { fmul f73, f67, f61 ; fmin f75, f69, f72 }
        { feq r34, f5, f35 ; fmax f78, f69, f72 }
        { fsel f83, r58, f37, f36 ; fneg f85, f82 }
        { fmul f71, f65, f62 ; fmul f74, f68, f62 }
        { fmin f76, f70, f73 ; fmax f79, f70, f73 }
        { fsel f75, r33, f81, f75 ; fsel f78, r33, f84, f78 }
        { feq r35, f6, f35 ; fneg f86, f83 }
        { fmin f77, f71, f74 ; fmax f80, f71, f74 }
        { fsel f76, r34, f82, f76 ; fsel f79, r34, f85, f79 }
        { fmax f40, f7, f75 ; fmin f9, f8, f78 }
        { fsel f77, r35, f83, f77 ; fsel f80, r35, f86, f80 }
        { fmax f40, f40, f76 ; fmin f9, f9, f79 }
        { fmax f40, f40, f77 ; fmin f9, f9, f80 }
        { fle r59, f40, f9 }
        { beqz r59, miss }

# ---- dda_setup, part 2: entry voxel, per-axis next/delta/step, state table --------------------
setup2:
        { fmul f88, f40, f5 ; fmul f89, f40, f6 }
        { fmul f87, f40, f4 ; fadd f91, f2, f88 }
        { fadd f90, f1, f87 ; fadd f92, f3, f89 }
        { fsub f93, f90, f20 ; fsub f94, f91, f21 }
        { fsub f95, f92, f22 ; fmul f96, f93, f29 }
        { fmul f97, f94, f30 ; fmin f96, f32, f96 }
        { fmul f98, f95, f31 ; fmax f96, f35, f96 }
        { fmin f97, f33, f97 ; fmin f98, f34, f98 }
        { fmax f97, f35, f97 ; fmax f98, f35, f98 }
        { ftoi r40, f97 ; ftoi r41, f98 }
        { fabs f120, f60 ; fabs f121, f61 ; mul r46, r40, r21 ; mul r47, r41, r22 }
        { ftoi r39, f96 ; fmul f123, f26, f120 ; add r48, r46, r47 }
        { flt r36, f35, f4 ; fabs f122, f62 ; add r48, r48, r39 }
        { add r42, r39, r36 ; fmul f124, f27, f121 ; fsel f16, r33, f36, f123 ; add r4, r48, r23 }
        { flt r37, f35, f5 ; itof f105, r42 ; lbu r8, 0(r4) ; fsw f1, ST_O(r1) }
        { flt r38, f35, f6 ; add r43, r40, r37 ; fsel f17, r34, f36, f124 ; fsw f2, ST_O+4(r1) }
        { add r44, r41, r38 ; itof f106, r43 ; fmul f125, f28, f122 ; fsw f3, ST_O+8(r1) }
        { itof f107, r44 ; fmul f109, f106, f27 ; sel r5, r36, r20, r24 ; fsw f4, ST_D(r1) }
        { fmul f110, f107, f28 ; fadd f112, f21, f109 ; sel r6, r37, r21, r25 ; fsw f5, ST_D+4(r1) }
        { fadd f113, f22, f110 ; fsel f18, r35, f36, f125 ; sel r7, r38, r22, r26 ; fsw f6, ST_D+8(r1) }
        { fmul f108, f105, f26 ; fsub f116, f113, f3 ; fsw f7, ST_TMIN(r1) }
        { fadd f111, f20, f108 ; fmul f119, f116, f62 ; fsw f8, ST_TMAX(r1) }
        { fsub f114, f111, f1 ; fsel f12, r35, f36, f119 ; fsw f9, ST_TEXIT(r1) }
        { fsub f115, f112, f2 ; fmul f117, f114, f60 ; fsw f16, ST_DELTA(r1) }
        { fmul f118, f115, f61 ; fsel f10, r33, f36, f117 ; fsw f17, ST_DELTA+4(r1) }
        { fsel f11, r34, f36, f118 ; fsw f18, ST_DELTA+8(r1) }
        { sw r5, ST_ASTEP(r1) }
        { sw r6, ST_ASTEP+4(r1) }
        { sw r7, ST_ASTEP+8(r1) ; bnez r8, visit_setup }

# ---- the voxel-step loop: two steps (A -> B, B -> A) per 10 bundles, II = 5 -------------------
enter_loop:
        { fle r9, f10, f11 ; li r8, 0 }
loop:
        { fle r10, f10, f12 ; fle r11, f11, f12 ; bnez r8, leave_b }
        { and r12, r9, r10 ; sel r13, r11, r6, r7 ; fadd f19, f10, f16 ; fadd f50, f11, f17 }
        { sel r14, r12, r5, r13 ; fsel f52, r11, f50, f11 ; fsel f13, r12, f19, f10 }
        { add r4, r4, r14 ; or r15, r10, r11 ; fsel f14, r9, f11, f52 ; fadd f51, f12, f18 }
        { lbu r8, 0(r4) ; fsel f15, r15, f12, f51 ; fle r9, f13, f14 }
        { bnez r8, leave_a ; fle r10, f13, f15 ; fle r11, f14, f15 }
        { and r12, r9, r10 ; sel r13, r11, r6, r7 ; fadd f19, f13, f16 ; fadd f50, f14, f17 }
        { sel r14, r12, r5, r13 ; fsel f52, r11, f50, f14 ; fsel f10, r12, f19, f13 }
        { add r4, r4, r14 ; or r15, r10, r11 ; fsel f11, r9, f14, f52 ; fadd f51, f15, f18 }
        { lbu r8, 0(r4) ; fsel f12, r15, f15, f51 ; fle r9, f10, f11 ; jmp loop }

# ---- leaving after an A -> B step: old nexts in A, new in B -----------------------------------
leave_a:
        { beq r8, r18, miss ; fsel f42, r15, f11, f12 ; fmin f43, f13, f14 }
        { fsel f40, r12, f10, f42 ; fmin f44, f43, f15 }
        { flt r59, f9, f40 ; fmin f41, f44, f9 }
        { bnez r59, miss }
visit_b:
        { iu0: sub r62, r4, r16 ; iu1: fsw f13, ST_NEXT(r1) ; fpu0: send CH_OS_IC, r3 }
        { iu0: send CH_OS_IC, r62 ; iu1: fsw f14, ST_NEXT+4(r1) ; fpu0: fsend CH_OS_IC, f40 ; fpu1: fsend CH_OS_IC, f41 }
        { iu0: fsend CH_OS_IC, f1 ; iu1: fsw f15, ST_NEXT+8(r1) ; fpu0: fsend CH_OS_IC, f2 ; fpu1: fsend CH_OS_IC, f3 }
        { iu0: fsend CH_OS_IC, f4 ; iu1: sw r4, ST_ADDR(r1) ; fpu0: fsend CH_OS_IC, f5 ; fpu1: fsend CH_OS_IC, f6 }
        { iu0: jmp next_ray ; iu1: fsw f40, ST_TIN(r1) ; fpu0: fsend CH_OS_IC, f7 ; fpu1: fsend CH_OS_IC, f8 }

# ---- leaving after a B -> A step: old nexts in B, new in A -----------------------------------
leave_b:
        { beq r8, r18, miss ; fsel f42, r15, f14, f15 ; fmin f43, f10, f11 }
        { fsel f40, r12, f13, f42 ; fmin f44, f43, f12 }
        { flt r59, f9, f40 ; fmin f41, f44, f9 }
        { bnez r59, miss }
visit_a:
        { iu0: sub r62, r4, r16 ; iu1: fsw f10, ST_NEXT(r1) ; fpu0: send CH_OS_IC, r3 }
        { iu0: send CH_OS_IC, r62 ; iu1: fsw f11, ST_NEXT+4(r1) ; fpu0: fsend CH_OS_IC, f40 ; fpu1: fsend CH_OS_IC, f41 }
        { iu0: fsend CH_OS_IC, f1 ; iu1: fsw f12, ST_NEXT+8(r1) ; fpu0: fsend CH_OS_IC, f2 ; fpu1: fsend CH_OS_IC, f3 }
        { iu0: fsend CH_OS_IC, f4 ; iu1: sw r4, ST_ADDR(r1) ; fpu0: fsend CH_OS_IC, f5 ; fpu1: fsend CH_OS_IC, f6 }
        { iu0: jmp next_ray ; iu1: fsw f40, ST_TIN(r1) ; fpu0: fsend CH_OS_IC, f7 ; fpu1: fsend CH_OS_IC, f8 }

# ---- the entry voxel is not empty: its exit, then the common VISIT ---------------------------
visit_setup:
        fmin f43, f10, f11
        fmin f44, f43, f12
        { fmin f41, f44, f9 ; jmp visit_a }

# ---- MISS: the ray left the grid, or passed t_exit ------------------------------------------
miss:
        { send CH_OS_SC, r64 ; jmp next_ray }

# ---- RETURN: a ray back from the IC resumes from its saved state ------------------------------
resume:
        { slli r45, r45, OS_STATE_SHIFT ; or r3, r2, r19 }
        { add r1, r17, r45 ; xor r64, r3, r19 }
        { flw f10, ST_NEXT(r1) ; flw f11, ST_NEXT+4(r1) }
        { flw f12, ST_NEXT+8(r1) ; lw r4, ST_ADDR(r1) ; fle r9, f10, f11 }
        { lw r5, ST_ASTEP(r1) ; lw r6, ST_ASTEP+4(r1) }
        { lw r7, ST_ASTEP+8(r1) ; flw f16, ST_DELTA(r1) }
        { flw f17, ST_DELTA+4(r1) ; flw f18, ST_DELTA+8(r1) }
        { flw f9, ST_TEXIT(r1) ; flw f1, ST_O(r1) }
        { flw f2, ST_O+4(r1) ; flw f3, ST_O+8(r1) }
        { flw f4, ST_D(r1) ; flw f5, ST_D+4(r1) }
        { flw f6, ST_D+8(r1) ; flw f7, ST_TMIN(r1) }
        { flw f8, ST_TMAX(r1) ; li r8, 0 }
        { jmp loop }
