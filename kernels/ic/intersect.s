# machine: ic
# kernels/ic/intersect.s: the IC processor's intersection kernel (1 IU + 3 FPU): for the voxel of a
# VISIT, every primitive of its list (triangles by the plane-equation method, quadrics in the general
# form), the nearest hit with tmin < t <= t_out, t < tmax (shadow rays: any t < tmax), ties to the
# lower shape index; HIT to the SC, or the tag back to the OS (RETURN). Float operations exactly as
# the twins kernels/twins/triangle.hpp and quadric.hpp; protocol and memory layout: kernels/abi.hpp.
#
# GENERATED from kernels/ic/intersect.pk: `nesshi schedule` places each body's temporaries and
# list-schedules it into the bundles below (edit the .pk, then run kernels/tools/build.sh).
#
# The software pipeline: three primitives in flight
# A voxel list mixes kinds, so there is no single loop body to modulo-schedule. Instead every
# primitive m gets one straight-line body, chosen by a jump through a dispatch table (the record's
# first word is its CODE_* offset), and the body overlaps three primitives:
#   m-1  accept tail   fle/fle: the deferred range flags; mask the candidate t to +inf when a flag
#                      fails; flt t < bound; keep bound (= best t), record, u, v, front by fsel.
#                      Kind-independent: it only reads the candidate registers f16-f20, f47-f49.
#   m    head          the kind's math from payload buffer X (loaded by the previous body), ending
#                      in a candidate: masked t, u, v, front, record, and the values of the range
#                      tests (0 <= CPV, CQA <= CQB) that the next body's tail evaluates.
#   m+1  prefetch      its dispatch code and jump target, payload words 0..11 into buffer Y.
#   m+2                its list entry (the record address).
# Bodies come in two variants, A (reads buffer A f30-f46, base r10, prefetches into B) and B
# (the reverse): modulo variable expansion of the payload buffer. The .pk writes the A bodies
# once; `#copy` makes the B bodies from them, placed after the rest of the kernel. The END record (CODE_END)
# closes every list, so there is no count and no loop compare: `done` is just another target.
# The jump (jr, branch penalty 0) ends each body; nothing of m's head is left in flight.
#
# Triangle body (tri1_A): 20 bundles. Per primitive:
#   IU   17 ops (lw code, lw target, 12 flw, lw entry, addi, jr)             -> >= 17 cycles
#   FPU  49 ops (15 fmul, 15 fadd, fneg, fdiv, 2 flt, 4+2 fsel, fmin, fmov, movif, tail 2 fle + flt)
#                                                                            -> >= 16.3 cycles
#   FPRF writes 56 (12 loads + 44 results) on 3 write ports                  -> >= 18.7 cycles
#   ResMII = 18.7 (FPRF write ports), RecMII = 2 (bound -> flt -> fsel -> bound).
# The remaining 1.3 cycles: the head's dependence chain (dn, on -> fneg -> fdiv (4) -> p -> a, b
# -> a + b) is about 17 cycles long and cannot start before the body does.
# Quadric bodies (the twin's general form: about 46 fmul + 44 fadd + sqrt + 2 fdiv):
#   quad1 / quad2   41 / 47 bundles   with the axial clip (cylinders, cones); ResMII 39.3 (FPRF writes)
#   sph1 / sph2     37 / 40           axis and length zero (CODE_SPH*): the clip is exactly a no-op
#   ball1           24                one-sided, M = I, g = 0, J < 0 (CODE_BALL1, plain spheres): the
#                                     products by 1 and sums with +-0 are exact, so M d = d and
#                                     M q + g/2 = q (kernels/image.hpp argues the signs of zeros);
#                                     ResMII 21.3; the rest is the chain p -> t0 -> q -> b, c ->
#                                     disc -> sqrt (4) -> fdiv (4) -> t.
# One-sided unclipped bodies end with the root itself: its test t > tmin is left to the next
# body's tail as the non-strict tmin_up <= t (tmin_up = the float above tmin, made per ray; exact
# for tmin >= 0), which takes two operations off the end of the chain.
#
# Register allocation
#   r1 list pointer (entry m+2)  r2 tag  r3 voxel  r10 r11 record base A/B  r13 jump target  r14 code
#   r20 voxel table  r23 shadow flag  r30 r31 head flags  r32 r33 tail flags  r34 accept flag
#   f1-f3 o  f4-f6 d  f7 tmin  f8 tmax  f9 t_out  f10 bound = best t  f12 best record (bits)
#   f13 f14 best u, v  f15 best front  f16-f20 candidate t, u, v, front, record  f21 +inf f22 -inf
#   f23 0  f24 1  f28 tmin_up  f30-f46 payload buffer A  f50-f66 buffer B  f47-f49 range-test values
#   f67 masked candidate  f71-f127 head temporaries (%v1, %v2, ... in the .pk; linear scan)
                .include "../abi.inc"
                .text
start:
        { li r0, 0 ; fli f23, 0.0 ; fli f24, 1.0 }
        { li r60, 0x7f800000 }
        { li r61, 0xff800000 ; movif f21, r60 }
        { movif f22, r61 ; lw r20, IC_HEADER+ICH_VOXTAB(r0) }
        { li r62, tri1_A }
        { sw r62, IC_JUMPS_A+0(r0) }
        { li r62, tri2_A }
        { sw r62, IC_JUMPS_A+4(r0) }
        { li r62, quad1_A }
        { sw r62, IC_JUMPS_A+8(r0) }
        { li r62, quad2_A }
        { sw r62, IC_JUMPS_A+12(r0) }
        { li r62, sph1_A }
        { sw r62, IC_JUMPS_A+20(r0) }
        { li r62, sph2_A }
        { sw r62, IC_JUMPS_A+24(r0) }
        { li r62, ball1_A }
        { sw r62, IC_JUMPS_A+28(r0) }
        { li r62, done }
        { sw r62, IC_JUMPS_A+16(r0) }
        { li r62, tri1_B }
        { sw r62, IC_JUMPS_B+0(r0) }
        { li r62, tri2_B }
        { sw r62, IC_JUMPS_B+4(r0) }
        { li r62, quad1_B }
        { sw r62, IC_JUMPS_B+8(r0) }
        { li r62, quad2_B }
        { sw r62, IC_JUMPS_B+12(r0) }
        { li r62, sph1_B }
        { sw r62, IC_JUMPS_B+20(r0) }
        { li r62, sph2_B }
        { sw r62, IC_JUMPS_B+24(r0) }
        { li r62, ball1_B }
        { sw r62, IC_JUMPS_B+28(r0) }
        { li r62, done }
        { sw r62, IC_JUMPS_B+16(r0) }

# ---- receive a VISIT: tag, voxel, t_in, t_out, o, d, tmin, tmax ----
next_ray:
        { iu0: recv r2, CH_IN ; fpu0: recv r3, CH_IN ; fpu1: frecv f25, CH_IN ; fpu2: frecv f9, CH_IN }
        { iu0: slli r5, r3, 2 ; fpu0: frecv f1, CH_IN ; fpu1: frecv f2, CH_IN ; fpu2: movfi r7, f9 }
        { iu0: andi r6, r2, TAG_KIND_MASK << TAG_KIND_SHIFT ; fpu0: frecv f3, CH_IN ; fpu1: frecv f4, CH_IN ; fpu2: frecv f5, CH_IN }
        { iu0: add r5, r5, r20 ; fpu0: frecv f6, CH_IN ; fpu1: frecv f7, CH_IN ; fpu2: frecv f8, CH_IN }
        { addi r7, r7, 1 ; movfi r8, f7 ; fmov f16, f21 ; fmov f12, f23 }
        { lw r1, 0(r5) ; movif f26, r7 }
        { addi r6, r6, -(KIND_SHADOW << TAG_KIND_SHIFT) ; fmin f27, f26, f8 }
        { lw r10, 0(r1) ; fsel f10, r6, f27, f8 }
        { addi r8, r8, 1 }
        { lw r14, REC_CODE(r10) ; movif f28, r8 }
        { lw r11, 4(r1) }
        { addi r1, r1, 8 }
        { flw f30, REC_W+0(r10) }
        { flw f31, REC_W+4(r10) }
        { flw f32, REC_W+8(r10) }
        { flw f33, REC_W+12(r10) }
        { flw f34, REC_W+16(r10) }
        { flw f35, REC_W+20(r10) }
        { flw f36, REC_W+24(r10) }
        { flw f37, REC_W+28(r10) }
        { flw f38, REC_W+32(r10) }
        { flw f39, REC_W+36(r10) }
        { flw f40, REC_W+40(r10) }
        { flw f41, REC_W+44(r10) }
        { lw r13, IC_JUMPS_A(r14) }
        { jr r13 }


tri1_A:
        { lw r14, REC_CODE(r11) ; fmul f76, f30, f1 ; fmul f77, f31, f2 ; fmul f78, f32, f3 }
        { lw r13, IC_JUMPS_B(r14) ; fmul f71, f30, f4 ; fmul f72, f31, f5 ; fadd f79, f76, f77 }
        { fle r32, f23, f47 ; flw f50, REC_W+0(r11) ; fmul f73, f32, f6 ; fadd f80, f79, f78 }
        { fle r33, f48, f49 ; flw f51, REC_W+4(r11) ; fadd f74, f71, f72 ; fadd f81, f80, f33 }
        { flw f52, REC_W+8(r11) ; fadd f75, f74, f73 ; fneg f82, f81 }
        { fsel f67, r32, f16, f21 ; flw f53, REC_W+12(r11) ; fdiv f83, f82, f75 ; flt r30, f75, f23 }
        { fsel f67, r33, f67, f21 ; flw f54, REC_W+16(r11) ; fmov f49, f24 }
        { flt r34, f67, f10 ; flw f55, REC_W+20(r11) }
        { fsel f12, r34, f20, f12 ; flw f56, REC_W+24(r11) }
        { flw f57, REC_W+28(r11) ; fmul f84, f83, f4 ; fmul f86, f83, f5 ; flt r31, f7, f83 }
        { flw f58, REC_W+32(r11) ; fadd f85, f1, f84 ; fadd f87, f2, f86 }
        { flw f59, REC_W+36(r11) ; fmul f88, f83, f6 ; fmul f90, f34, f85 }
        { flw f60, REC_W+40(r11) ; fadd f89, f3, f88 ; fmul f91, f35, f87 }
        { flw f61, REC_W+44(r11) ; fmul f95, f38, f85 ; fmul f96, f39, f87 }
        { fmul f92, f36, f89 ; fadd f93, f90, f91 ; fmul f97, f40, f89 }
        { fadd f94, f93, f92 ; fadd f98, f95, f96 ; movif f20, r10 ; lw r10, 0(r1) }
        { fsel f13, r34, f17, f13 ; fsel f14, r34, f18, f14 ; fadd f99, f98, f97 ; addi r1, r1, 4 }
        { fadd f17, f94, f37 ; fadd f18, f99, f41 ; fsel f100, r30, f83, f21 }
        { fsel f10, r34, f67, f10 ; fsel f15, r34, f19, f15 ; fadd f48, f17, f18 }
        { fsel f16, r31, f100, f21 ; fmin f47, f17, f18 ; jr r13 }

tri2_A:
        { lw r14, REC_CODE(r11) ; fmul f76, f30, f1 ; fmul f77, f31, f2 ; fmul f78, f32, f3 }
        { lw r13, IC_JUMPS_B(r14) ; fmul f71, f30, f4 ; fmul f72, f31, f5 ; fadd f79, f76, f77 }
        { fle r32, f23, f47 ; flw f50, REC_W+0(r11) ; fmul f73, f32, f6 ; fadd f80, f79, f78 }
        { fle r33, f48, f49 ; flw f51, REC_W+4(r11) ; fadd f74, f71, f72 ; fadd f81, f80, f33 }
        { flw f52, REC_W+8(r11) ; fadd f75, f74, f73 ; fneg f82, f81 }
        { fsel f67, r32, f16, f21 ; flw f53, REC_W+12(r11) ; fdiv f83, f82, f75 ; feq r30, f75, f23 }
        { fsel f67, r33, f67, f21 ; flw f54, REC_W+16(r11) ; fmov f49, f24 }
        { flt r34, f67, f10 ; flw f55, REC_W+20(r11) }
        { fsel f12, r34, f20, f12 ; flw f56, REC_W+24(r11) }
        { flw f57, REC_W+28(r11) ; fmul f84, f83, f4 ; fmul f86, f83, f5 ; flt r31, f7, f83 }
        { flw f58, REC_W+32(r11) ; fadd f85, f1, f84 ; fadd f87, f2, f86 }
        { flw f59, REC_W+36(r11) ; fmul f88, f83, f6 ; fmul f90, f34, f85 }
        { flw f60, REC_W+40(r11) ; fadd f89, f3, f88 ; fmul f91, f35, f87 }
        { flw f61, REC_W+44(r11) ; fmul f95, f38, f85 ; fmul f96, f39, f87 }
        { fmul f92, f36, f89 ; fadd f93, f90, f91 ; fmul f97, f40, f89 }
        { fadd f94, f93, f92 ; fadd f98, f95, f96 ; movif f20, r10 ; lw r10, 0(r1) }
        { fsel f13, r34, f17, f13 ; fsel f14, r34, f18, f14 ; fadd f99, f98, f97 ; addi r1, r1, 4 }
        { fadd f17, f94, f37 ; fadd f18, f99, f41 ; fsel f100, r30, f21, f83 }
        { fsel f10, r34, f67, f10 ; fsel f15, r34, f19, f15 ; fadd f48, f17, f18 }
        { fsel f16, r31, f100, f21 ; fmin f47, f17, f18 ; jr r13 }

quad1_A:
        { lw r14, REC_CODE(r11) ; fsub f71, f1, f30 ; fsub f72, f2, f31 ; fsub f73, f3, f32 }
        { lw r13, IC_JUMPS_B(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f33, f4 ; fmul f87, f36, f5 }
        { fadd f78, f77, f76 ; fmul f91, f36, f4 ; fmul f92, f34, f5 }
        { fmul f88, f38, f6 ; fmul f93, f37, f6 ; fmul f96, f38, f4 }
        { fneg f79, f78 ; fadd f89, f86, f87 ; fmul f97, f37, f5 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f33, f81 ; fmul f102, f36, f83 ; fmul f107, f36, f81 }
        { fmul f103, f38, f85 ; fmul f108, f34, f83 ; fmul f109, f37, f85 }
        { fadd f104, f101, f102 ; fadd f110, f107, f108 ; fmul f113, f38, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f37, f83 }
        { fadd f106, f105, f39 ; fadd f112, f111, f40 ; fmul f115, f35, f85 }
        { fadd f116, f113, f114 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fadd f117, f116, f115 ; fadd f78, f75, f77 ; fmul f80, f39, f81 }
        { fadd f118, f117, f41 ; fmul f72, f40, f83 ; fmul f82, f41, f85 }
        { fadd f94, f91, f92 ; fmul f76, f85, f118 ; fadd f73, f80, f72 }
        { fmul f98, f35, f6 ; fadd f71, f78, f76 ; fadd f84, f73, f82 }
        { fadd f90, f89, f88 ; fadd f99, f96, f97 ; fadd f86, f71, f84 }
        { fadd f95, f94, f93 ; fadd f100, f99, f98 ; fmul f119, f4, f90 }
        { fle r32, f23, f47 ; flw f42, REC_W+48(r10) ; fmul f120, f5, f95 ; fmul f121, f6, f100 }
        { fle r33, f48, f49 ; flw f43, REC_W+52(r10) ; fadd f122, f119, f120 ; fmul f124, f4, f106 }
        { flw f44, REC_W+56(r10) ; fadd f123, f122, f121 ; fmul f125, f5, f112 }
        { flw f45, REC_W+60(r10) ; fadd f127, f124, f125 ; fadd f87, f86, f42 }
        { flw f49, REC_W+64(r10) ; fmul f126, f6, f118 ; fmul f88, f123, f87 }
        { flw f50, REC_W+0(r11) ; fadd f74, f127, f126 ; fmul f103, f43, f4 }
        { flw f51, REC_W+4(r11) ; fmul f89, f74, f74 ; fmul f105, f44, f5 }
        { flw f52, REC_W+8(r11) ; fsub f91, f89, f88 ; fmul f107, f45, f6 }
        { fsel f67, r32, f16, f21 ; flw f53, REC_W+12(r11) ; fsqrt f92, f91 ; fneg f94, f74 }
        { flw f54, REC_W+16(r11) ; fmul f99, f43, f81 ; fadd f108, f103, f105 }
        { flw f55, REC_W+20(r11) ; fmul f98, f44, f83 ; fadd f110, f108, f107 }
        { flw f56, REC_W+24(r11) ; fmul f101, f45, f85 }
        { fsel f67, r33, f67, f21 ; flw f57, REC_W+28(r11) ; fsub f93, f94, f92 }
        { flt r34, f67, f10 ; flw f58, REC_W+32(r11) ; fdiv f96, f93, f123 ; fadd f102, f99, f98 }
        { fsel f12, r34, f20, f12 ; movif f20, r10 ; fadd f104, f102, f101 ; lw r10, 0(r1) }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; fsel f14, r34, f18, f14 ; addi r1, r1, 4 }
        { fsel f15, r34, f19, f15 ; flw f59, REC_W+36(r11) }
        { flw f60, REC_W+40(r11) ; fadd f97, f79, f96 ; fmul f109, f96, f110 }
        { flw f61, REC_W+44(r11) ; fadd f47, f104, f109 ; flt r30, f7, f97 ; fmov f19, f24 }
        { fsel f16, r30, f97, f21 ; fmov f48, f47 ; jr r13 }

quad2_A:
        { lw r14, REC_CODE(r11) ; fsub f71, f1, f30 ; fsub f72, f2, f31 ; fsub f73, f3, f32 }
        { lw r13, IC_JUMPS_B(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f33, f4 ; fmul f87, f36, f5 }
        { fadd f78, f77, f76 ; fmul f91, f36, f4 ; fmul f92, f34, f5 }
        { fmul f88, f38, f6 ; fmul f93, f37, f6 ; fmul f96, f38, f4 }
        { fneg f79, f78 ; fadd f89, f86, f87 ; fmul f97, f37, f5 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f33, f81 ; fmul f102, f36, f83 ; fmul f107, f36, f81 }
        { fmul f103, f38, f85 ; fmul f108, f34, f83 ; fmul f109, f37, f85 }
        { fadd f104, f101, f102 ; fadd f110, f107, f108 ; fmul f113, f38, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f37, f83 }
        { fadd f106, f105, f39 ; fadd f112, f111, f40 ; fmul f115, f35, f85 }
        { fadd f116, f113, f114 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fadd f117, f116, f115 ; fadd f78, f75, f77 ; fmul f80, f39, f81 }
        { fadd f118, f117, f41 ; fmul f72, f40, f83 ; fmul f82, f41, f85 }
        { fadd f94, f91, f92 ; fmul f76, f85, f118 ; fadd f73, f80, f72 }
        { fmul f98, f35, f6 ; fadd f71, f78, f76 ; fadd f84, f73, f82 }
        { fadd f90, f89, f88 ; fadd f99, f96, f97 ; fadd f86, f71, f84 }
        { fadd f95, f94, f93 ; fadd f100, f99, f98 ; fmul f119, f4, f90 }
        { fmul f120, f5, f95 ; fmul f121, f6, f100 ; fmul f124, f4, f106 }
        { fadd f122, f119, f120 ; fmul f125, f5, f112 ; fmul f126, f6, f118 }
        { fle r32, f23, f47 ; flw f42, REC_W+48(r10) ; fadd f123, f122, f121 ; fadd f127, f124, f125 }
        { fle r33, f48, f49 ; flw f43, REC_W+52(r10) ; fadd f74, f127, f126 ; fadd f87, f86, f42 }
        { fmul f89, f74, f74 ; fmul f88, f123, f87 ; fneg f94, f74 }
        { flw f44, REC_W+56(r10) ; fsub f91, f89, f88 ; fmul f102, f43, f81 }
        { flw f45, REC_W+60(r10) ; fsqrt f92, f91 ; fmul f104, f44, f83 ; fmul f108, f43, f4 }
        { fmul f103, f45, f85 ; fadd f105, f102, f104 ; fmul f110, f44, f5 }
        { fadd f107, f105, f103 ; fmul f109, f45, f6 ; fadd f111, f108, f110 }
        { fsel f67, r32, f16, f21 ; flw f46, REC_W+64(r10) }
        { flw f50, REC_W+0(r11) ; fsub f93, f94, f92 ; fadd f99, f94, f92 }
        { fsel f67, r33, f67, f21 ; flw f51, REC_W+4(r11) ; fdiv f96, f93, f123 ; fdiv f98, f99, f123 }
        { flt r34, f67, f10 ; flw f52, REC_W+8(r11) ; fadd f113, f111, f109 ; fmov f47, f23 }
        { fsel f12, r34, f20, f12 ; flw f53, REC_W+12(r11) ; movif f20, r10 }
        { flw f54, REC_W+16(r11) }
        { fadd f97, f79, f96 ; fadd f101, f79, f98 ; fmul f114, f96, f113 ; lw r10, 0(r1) }
        { flw f55, REC_W+20(r11) ; fmul f115, f98, f113 ; flt r30, f7, f97 ; flt r37, f7, f101 }
        { fadd f116, f107, f114 ; fadd f117, f107, f115 ; fsel f119, r37, f101, f21 ; addi r1, r1, 4 }
        { flw f56, REC_W+24(r11) ; fsel f90, r30, f97, f21 ; fle r38, f23, f117 ; fle r39, f117, f46 }
        { flw f57, REC_W+28(r11) ; fle r31, f23, f116 ; fle r36, f116, f46 ; fsel f120, r38, f119, f21 }
        { flw f58, REC_W+32(r11) ; fsel f95, r31, f90, f21 ; fsel f122, r39, f120, f21 }
        { fsel f15, r34, f19, f15 ; flw f59, REC_W+36(r11) ; fsel f100, r36, f95, f21 }
        { fsel f10, r34, f67, f10 ; flw f60, REC_W+40(r11) ; fle r40, f100, f122 ; fmin f16, f122, f100 }
        { fsel f13, r34, f17, f13 ; flw f61, REC_W+44(r11) ; fsel f19, r40, f24, f23 }
        { fsel f14, r34, f18, f14 ; fmov f48, f23 ; fmov f49, f24 ; jr r13 }

sph1_A:
        { lw r14, REC_CODE(r11) ; fsub f71, f1, f30 ; fsub f72, f2, f31 ; fsub f73, f3, f32 }
        { lw r13, IC_JUMPS_B(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f33, f4 ; fmul f87, f36, f5 }
        { fadd f78, f77, f76 ; fmul f91, f36, f4 ; fmul f92, f34, f5 }
        { fneg f79, f78 ; fmul f88, f38, f6 ; fadd f89, f86, f87 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f33, f81 ; fmul f102, f36, f83 ; fmul f107, f36, f81 }
        { fmul f103, f38, f85 ; fadd f104, f101, f102 ; fmul f108, f34, f83 }
        { fmul f109, f37, f85 ; fadd f110, f107, f108 ; fmul f113, f38, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f37, f83 }
        { fadd f106, f105, f39 ; fmul f115, f35, f85 ; fadd f116, f113, f114 }
        { fmul f93, f37, f6 ; fadd f112, f111, f40 ; fadd f117, f116, f115 }
        { fadd f94, f91, f92 ; fmul f96, f38, f4 ; fmul f97, f37, f5 }
        { fadd f118, f117, f41 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fle r32, f23, f47 ; flw f50, REC_W+0(r11) ; fmul f80, f39, f81 ; fmul f72, f40, f83 }
        { fadd f90, f89, f88 ; fadd f95, f94, f93 ; fmul f98, f35, f6 }
        { fadd f99, f96, f97 ; fmul f76, f85, f118 ; fadd f78, f75, f77 }
        { fle r33, f48, f49 ; flw f51, REC_W+4(r11) ; fmul f82, f41, f85 ; fadd f73, f80, f72 }
        { fadd f100, f99, f98 ; fmul f119, f4, f90 ; fmul f120, f5, f95 }
        { fmul f124, f4, f106 ; fmul f125, f5, f112 ; fadd f71, f78, f76 }
        { flw f52, REC_W+8(r11) ; fmul f121, f6, f100 ; fadd f84, f73, f82 }
        { flw f42, REC_W+48(r10) ; fadd f122, f119, f120 ; fmul f126, f6, f118 }
        { flw f53, REC_W+12(r11) ; fadd f127, f124, f125 ; fadd f86, f71, f84 }
        { fadd f123, f122, f121 ; fadd f74, f127, f126 ; fadd f87, f86, f42 }
        { flw f54, REC_W+16(r11) ; fmul f89, f74, f74 ; fmul f88, f123, f87 }
        { flw f55, REC_W+20(r11) ; fsub f91, f89, f88 ; fneg f94, f74 }
        { fsel f67, r32, f16, f21 ; flw f56, REC_W+24(r11) ; fsqrt f92, f91 ; fmov f47, f23 }
        { fsel f67, r33, f67, f21 ; flw f57, REC_W+28(r11) ; fmov f48, f28 }
        { flt r34, f67, f10 ; flw f58, REC_W+32(r11) }
        { fsel f12, r34, f20, f12 ; flw f59, REC_W+36(r11) }
        { flw f60, REC_W+40(r11) ; movif f20, r10 ; fsub f93, f94, f92 }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; flw f61, REC_W+44(r11) ; fdiv f96, f93, f123 }
        { fsel f14, r34, f18, f14 ; fsel f15, r34, f19, f15 ; fmov f19, f24 ; lw r10, 0(r1) }
        { addi r1, r1, 4 }
        nop
        { fadd f16, f79, f96 ; fadd f49, f79, f96 ; jr r13 }

sph2_A:
        { lw r14, REC_CODE(r11) ; fsub f71, f1, f30 ; fsub f72, f2, f31 ; fsub f73, f3, f32 }
        { lw r13, IC_JUMPS_B(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f33, f4 ; fmul f87, f36, f5 }
        { fadd f78, f77, f76 ; fmul f91, f36, f4 ; fmul f92, f34, f5 }
        { fneg f79, f78 ; fmul f88, f38, f6 ; fadd f89, f86, f87 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f33, f81 ; fmul f102, f36, f83 ; fmul f107, f36, f81 }
        { fmul f103, f38, f85 ; fadd f104, f101, f102 ; fmul f108, f34, f83 }
        { fmul f109, f37, f85 ; fadd f110, f107, f108 ; fmul f113, f38, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f37, f83 }
        { fadd f106, f105, f39 ; fmul f115, f35, f85 ; fadd f116, f113, f114 }
        { fmul f93, f37, f6 ; fadd f112, f111, f40 ; fadd f117, f116, f115 }
        { fadd f94, f91, f92 ; fmul f96, f38, f4 ; fmul f97, f37, f5 }
        { fadd f118, f117, f41 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fadd f90, f89, f88 ; fmul f80, f39, f81 ; fmul f72, f40, f83 }
        { fadd f95, f94, f93 ; fmul f98, f35, f6 ; fadd f99, f96, f97 }
        { fmul f76, f85, f118 ; fadd f78, f75, f77 ; fmul f82, f41, f85 }
        { fadd f100, f99, f98 ; fmul f119, f4, f90 ; fadd f73, f80, f72 }
        { fmul f120, f5, f95 ; fmul f124, f4, f106 ; fmul f125, f5, f112 }
        { fle r32, f23, f47 ; flw f42, REC_W+48(r10) ; fadd f71, f78, f76 ; fadd f84, f73, f82 }
        { fmul f121, f6, f100 ; fadd f122, f119, f120 ; fmul f126, f6, f118 }
        { fadd f123, f122, f121 ; fadd f127, f124, f125 ; fadd f86, f71, f84 }
        { fle r33, f48, f49 ; flw f50, REC_W+0(r11) ; fadd f74, f127, f126 ; fadd f87, f86, f42 }
        { flw f51, REC_W+4(r11) ; fmul f89, f74, f74 ; fmul f88, f123, f87 }
        { flw f52, REC_W+8(r11) ; fsub f91, f89, f88 ; fneg f94, f74 }
        { fsel f67, r32, f16, f21 ; flw f53, REC_W+12(r11) ; fsqrt f92, f91 ; fmov f47, f23 }
        { fsel f67, r33, f67, f21 ; flw f54, REC_W+16(r11) ; fmov f48, f23 }
        { flt r34, f67, f10 ; flw f55, REC_W+20(r11) ; fmov f49, f24 }
        { fsel f12, r34, f20, f12 ; flw f56, REC_W+24(r11) }
        { flw f57, REC_W+28(r11) ; fsub f93, f94, f92 ; fadd f99, f94, f92 }
        { flw f58, REC_W+32(r11) ; movif f20, r10 ; fdiv f96, f93, f123 ; fdiv f98, f99, f123 }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; flw f59, REC_W+36(r11) }
        { fsel f14, r34, f18, f14 ; fsel f15, r34, f19, f15 ; flw f60, REC_W+40(r11) }
        { flw f61, REC_W+44(r11) }
        { fadd f97, f79, f96 ; fadd f101, f79, f98 ; lw r10, 0(r1) }
        { flt r30, f7, f97 ; flt r37, f7, f101 }
        { fsel f102, r30, f97, f21 ; fsel f104, r37, f101, f21 ; addi r1, r1, 4 }
        { fle r40, f102, f104 ; fmin f16, f104, f102 }
        { fsel f19, r40, f24, f23 ; jr r13 }

ball1_A:
        { lw r14, REC_CODE(r11) ; fsub f71, f1, f30 ; fsub f72, f2, f31 ; fsub f73, f3, f32 }
        { lw r13, IC_JUMPS_B(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fle r32, f23, f47 ; flw f50, REC_W+0(r11) ; fadd f77, f74, f75 ; fmul f86, f4, f4 }
        { fle r33, f48, f49 ; flw f51, REC_W+4(r11) ; fadd f78, f77, f76 ; fmul f87, f5, f5 }
        { flw f52, REC_W+8(r11) ; fneg f79, f78 ; fmul f88, f6, f6 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f91, f4, f81 ; fmul f96, f81, f81 ; fmul f97, f83, f83 }
        { fmul f92, f5, f83 ; fmul f98, f85, f85 ; fadd f99, f96, f97 }
        { flw f42, REC_W+48(r10) ; fadd f89, f86, f87 ; fmul f93, f6, f85 }
        { flw f53, REC_W+12(r11) ; fadd f94, f91, f92 ; fadd f100, f99, f98 }
        { fadd f90, f89, f88 ; fadd f95, f94, f93 ; fadd f101, f100, f42 }
        { flw f54, REC_W+16(r11) ; fmul f102, f95, f95 ; fmul f103, f90, f101 }
        { flw f55, REC_W+20(r11) ; fsub f104, f102, f103 ; fneg f106, f95 }
        { fsel f67, r32, f16, f21 ; flw f56, REC_W+24(r11) ; fsqrt f105, f104 ; fmov f47, f23 }
        { fsel f67, r33, f67, f21 ; flw f57, REC_W+28(r11) ; fmov f48, f28 }
        { flt r34, f67, f10 ; flw f58, REC_W+32(r11) }
        { fsel f12, r34, f20, f12 ; flw f59, REC_W+36(r11) }
        { flw f60, REC_W+40(r11) ; movif f20, r10 ; fsub f107, f106, f105 }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; flw f61, REC_W+44(r11) ; fdiv f108, f107, f90 }
        { fsel f14, r34, f18, f14 ; fsel f15, r34, f19, f15 ; fmov f19, f24 ; lw r10, 0(r1) }
        { addi r1, r1, 4 }
        nop
        { fadd f16, f79, f108 ; fadd f49, f79, f108 ; jr r13 }


# ---- end of the list: accept the last candidate, then HIT or RETURN ----
done:
        { fle r32, f23, f47 ; fle r33, f48, f49 }
        { fsel f67, r32, f16, f21 }
        { fsel f67, r33, f67, f21 }
        { flt r34, f67, f10 }
        { fsel f10, r34, f67, f10 ; fsel f12, r34, f20, f12 ; fsel f13, r34, f17, f13 }
        { fsel f14, r34, f18, f14 ; fsel f15, r34, f19, f15 ; movfi r7, f12 }
        { bnez r7, hit }
return:
        { iu0: jmp next_ray ; fpu0: send CH_IC_OS, r2 }

hit:
        { li r8, 0x7fffffff ; ftoi r12, f15 }
        { and r8, r2, r8 }
        { iu0: lw r9, REC_INDEX(r7) ; fpu0: send CH_IC_SC, r8 }
        { iu0: lw r15, REC_CODE(r7) ; fpu0: send CH_IC_SC, r9 ; fpu1: fsend CH_IC_SC, f10 }
        { slti r16, r15, CODE_QUAD1 }
        { li r17, 1 ; fsel f13, r16, f13, f23 ; fsel f14, r16, f14, f23 }
        { iu0: sel r12, r16, r17, r12 ; fpu0: fsend CH_IC_SC, f13 ; fpu1: fsend CH_IC_SC, f14 }
        { iu0: jmp next_ray ; fpu0: send CH_IC_SC, r12 }

# The B bodies: the A bodies with the payload buffers exchanged (read B f50-f66 at base r11,
# prefetch into A f30-f46 at base r10, dispatch through IC_JUMPS_A).

# ---- lines 156-918 copied by '#copy bodies' (line 968) ----
tri1_B:
        { lw r14, REC_CODE(r10) ; fmul f76, f50, f1 ; fmul f77, f51, f2 ; fmul f78, f52, f3 }
        { lw r13, IC_JUMPS_A(r14) ; fmul f71, f50, f4 ; fmul f72, f51, f5 ; fadd f79, f76, f77 }
        { fle r32, f23, f47 ; flw f30, REC_W+0(r10) ; fmul f73, f52, f6 ; fadd f80, f79, f78 }
        { fle r33, f48, f49 ; flw f31, REC_W+4(r10) ; fadd f74, f71, f72 ; fadd f81, f80, f53 }
        { flw f32, REC_W+8(r10) ; fadd f75, f74, f73 ; fneg f82, f81 }
        { fsel f67, r32, f16, f21 ; flw f33, REC_W+12(r10) ; fdiv f83, f82, f75 ; flt r30, f75, f23 }
        { fsel f67, r33, f67, f21 ; flw f34, REC_W+16(r10) ; fmov f49, f24 }
        { flt r34, f67, f10 ; flw f35, REC_W+20(r10) }
        { fsel f12, r34, f20, f12 ; flw f36, REC_W+24(r10) }
        { flw f37, REC_W+28(r10) ; fmul f84, f83, f4 ; fmul f86, f83, f5 ; flt r31, f7, f83 }
        { flw f38, REC_W+32(r10) ; fadd f85, f1, f84 ; fadd f87, f2, f86 }
        { flw f39, REC_W+36(r10) ; fmul f88, f83, f6 ; fmul f90, f54, f85 }
        { flw f40, REC_W+40(r10) ; fadd f89, f3, f88 ; fmul f91, f55, f87 }
        { flw f41, REC_W+44(r10) ; fmul f95, f58, f85 ; fmul f96, f59, f87 }
        { fmul f92, f56, f89 ; fadd f93, f90, f91 ; fmul f97, f60, f89 }
        { fadd f94, f93, f92 ; fadd f98, f95, f96 ; movif f20, r11 ; lw r11, 0(r1) }
        { fsel f13, r34, f17, f13 ; fsel f14, r34, f18, f14 ; fadd f99, f98, f97 ; addi r1, r1, 4 }
        { fadd f17, f94, f57 ; fadd f18, f99, f61 ; fsel f100, r30, f83, f21 }
        { fsel f10, r34, f67, f10 ; fsel f15, r34, f19, f15 ; fadd f48, f17, f18 }
        { fsel f16, r31, f100, f21 ; fmin f47, f17, f18 ; jr r13 }

tri2_B:
        { lw r14, REC_CODE(r10) ; fmul f76, f50, f1 ; fmul f77, f51, f2 ; fmul f78, f52, f3 }
        { lw r13, IC_JUMPS_A(r14) ; fmul f71, f50, f4 ; fmul f72, f51, f5 ; fadd f79, f76, f77 }
        { fle r32, f23, f47 ; flw f30, REC_W+0(r10) ; fmul f73, f52, f6 ; fadd f80, f79, f78 }
        { fle r33, f48, f49 ; flw f31, REC_W+4(r10) ; fadd f74, f71, f72 ; fadd f81, f80, f53 }
        { flw f32, REC_W+8(r10) ; fadd f75, f74, f73 ; fneg f82, f81 }
        { fsel f67, r32, f16, f21 ; flw f33, REC_W+12(r10) ; fdiv f83, f82, f75 ; feq r30, f75, f23 }
        { fsel f67, r33, f67, f21 ; flw f34, REC_W+16(r10) ; fmov f49, f24 }
        { flt r34, f67, f10 ; flw f35, REC_W+20(r10) }
        { fsel f12, r34, f20, f12 ; flw f36, REC_W+24(r10) }
        { flw f37, REC_W+28(r10) ; fmul f84, f83, f4 ; fmul f86, f83, f5 ; flt r31, f7, f83 }
        { flw f38, REC_W+32(r10) ; fadd f85, f1, f84 ; fadd f87, f2, f86 }
        { flw f39, REC_W+36(r10) ; fmul f88, f83, f6 ; fmul f90, f54, f85 }
        { flw f40, REC_W+40(r10) ; fadd f89, f3, f88 ; fmul f91, f55, f87 }
        { flw f41, REC_W+44(r10) ; fmul f95, f58, f85 ; fmul f96, f59, f87 }
        { fmul f92, f56, f89 ; fadd f93, f90, f91 ; fmul f97, f60, f89 }
        { fadd f94, f93, f92 ; fadd f98, f95, f96 ; movif f20, r11 ; lw r11, 0(r1) }
        { fsel f13, r34, f17, f13 ; fsel f14, r34, f18, f14 ; fadd f99, f98, f97 ; addi r1, r1, 4 }
        { fadd f17, f94, f57 ; fadd f18, f99, f61 ; fsel f100, r30, f21, f83 }
        { fsel f10, r34, f67, f10 ; fsel f15, r34, f19, f15 ; fadd f48, f17, f18 }
        { fsel f16, r31, f100, f21 ; fmin f47, f17, f18 ; jr r13 }

quad1_B:
        { lw r14, REC_CODE(r10) ; fsub f71, f1, f50 ; fsub f72, f2, f51 ; fsub f73, f3, f52 }
        { lw r13, IC_JUMPS_A(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f53, f4 ; fmul f87, f56, f5 }
        { fadd f78, f77, f76 ; fmul f91, f56, f4 ; fmul f92, f54, f5 }
        { fmul f88, f58, f6 ; fmul f93, f57, f6 ; fmul f96, f58, f4 }
        { fneg f79, f78 ; fadd f89, f86, f87 ; fmul f97, f57, f5 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f53, f81 ; fmul f102, f56, f83 ; fmul f107, f56, f81 }
        { fmul f103, f58, f85 ; fmul f108, f54, f83 ; fmul f109, f57, f85 }
        { fadd f104, f101, f102 ; fadd f110, f107, f108 ; fmul f113, f58, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f57, f83 }
        { fadd f106, f105, f59 ; fadd f112, f111, f60 ; fmul f115, f55, f85 }
        { fadd f116, f113, f114 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fadd f117, f116, f115 ; fadd f78, f75, f77 ; fmul f80, f59, f81 }
        { fadd f118, f117, f61 ; fmul f72, f60, f83 ; fmul f82, f61, f85 }
        { fadd f94, f91, f92 ; fmul f76, f85, f118 ; fadd f73, f80, f72 }
        { fmul f98, f55, f6 ; fadd f71, f78, f76 ; fadd f84, f73, f82 }
        { fadd f90, f89, f88 ; fadd f99, f96, f97 ; fadd f86, f71, f84 }
        { fadd f95, f94, f93 ; fadd f100, f99, f98 ; fmul f119, f4, f90 }
        { fle r32, f23, f47 ; flw f62, REC_W+48(r11) ; fmul f120, f5, f95 ; fmul f121, f6, f100 }
        { fle r33, f48, f49 ; flw f63, REC_W+52(r11) ; fadd f122, f119, f120 ; fmul f124, f4, f106 }
        { flw f64, REC_W+56(r11) ; fadd f123, f122, f121 ; fmul f125, f5, f112 }
        { flw f65, REC_W+60(r11) ; fadd f127, f124, f125 ; fadd f87, f86, f62 }
        { flw f49, REC_W+64(r11) ; fmul f126, f6, f118 ; fmul f88, f123, f87 }
        { flw f30, REC_W+0(r10) ; fadd f74, f127, f126 ; fmul f103, f63, f4 }
        { flw f31, REC_W+4(r10) ; fmul f89, f74, f74 ; fmul f105, f64, f5 }
        { flw f32, REC_W+8(r10) ; fsub f91, f89, f88 ; fmul f107, f65, f6 }
        { fsel f67, r32, f16, f21 ; flw f33, REC_W+12(r10) ; fsqrt f92, f91 ; fneg f94, f74 }
        { flw f34, REC_W+16(r10) ; fmul f99, f63, f81 ; fadd f108, f103, f105 }
        { flw f35, REC_W+20(r10) ; fmul f98, f64, f83 ; fadd f110, f108, f107 }
        { flw f36, REC_W+24(r10) ; fmul f101, f65, f85 }
        { fsel f67, r33, f67, f21 ; flw f37, REC_W+28(r10) ; fsub f93, f94, f92 }
        { flt r34, f67, f10 ; flw f38, REC_W+32(r10) ; fdiv f96, f93, f123 ; fadd f102, f99, f98 }
        { fsel f12, r34, f20, f12 ; movif f20, r11 ; fadd f104, f102, f101 ; lw r11, 0(r1) }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; fsel f14, r34, f18, f14 ; addi r1, r1, 4 }
        { fsel f15, r34, f19, f15 ; flw f39, REC_W+36(r10) }
        { flw f40, REC_W+40(r10) ; fadd f97, f79, f96 ; fmul f109, f96, f110 }
        { flw f41, REC_W+44(r10) ; fadd f47, f104, f109 ; flt r30, f7, f97 ; fmov f19, f24 }
        { fsel f16, r30, f97, f21 ; fmov f48, f47 ; jr r13 }

quad2_B:
        { lw r14, REC_CODE(r10) ; fsub f71, f1, f50 ; fsub f72, f2, f51 ; fsub f73, f3, f52 }
        { lw r13, IC_JUMPS_A(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f53, f4 ; fmul f87, f56, f5 }
        { fadd f78, f77, f76 ; fmul f91, f56, f4 ; fmul f92, f54, f5 }
        { fmul f88, f58, f6 ; fmul f93, f57, f6 ; fmul f96, f58, f4 }
        { fneg f79, f78 ; fadd f89, f86, f87 ; fmul f97, f57, f5 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f53, f81 ; fmul f102, f56, f83 ; fmul f107, f56, f81 }
        { fmul f103, f58, f85 ; fmul f108, f54, f83 ; fmul f109, f57, f85 }
        { fadd f104, f101, f102 ; fadd f110, f107, f108 ; fmul f113, f58, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f57, f83 }
        { fadd f106, f105, f59 ; fadd f112, f111, f60 ; fmul f115, f55, f85 }
        { fadd f116, f113, f114 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fadd f117, f116, f115 ; fadd f78, f75, f77 ; fmul f80, f59, f81 }
        { fadd f118, f117, f61 ; fmul f72, f60, f83 ; fmul f82, f61, f85 }
        { fadd f94, f91, f92 ; fmul f76, f85, f118 ; fadd f73, f80, f72 }
        { fmul f98, f55, f6 ; fadd f71, f78, f76 ; fadd f84, f73, f82 }
        { fadd f90, f89, f88 ; fadd f99, f96, f97 ; fadd f86, f71, f84 }
        { fadd f95, f94, f93 ; fadd f100, f99, f98 ; fmul f119, f4, f90 }
        { fmul f120, f5, f95 ; fmul f121, f6, f100 ; fmul f124, f4, f106 }
        { fadd f122, f119, f120 ; fmul f125, f5, f112 ; fmul f126, f6, f118 }
        { fle r32, f23, f47 ; flw f62, REC_W+48(r11) ; fadd f123, f122, f121 ; fadd f127, f124, f125 }
        { fle r33, f48, f49 ; flw f63, REC_W+52(r11) ; fadd f74, f127, f126 ; fadd f87, f86, f62 }
        { fmul f89, f74, f74 ; fmul f88, f123, f87 ; fneg f94, f74 }
        { flw f64, REC_W+56(r11) ; fsub f91, f89, f88 ; fmul f102, f63, f81 }
        { flw f65, REC_W+60(r11) ; fsqrt f92, f91 ; fmul f104, f64, f83 ; fmul f108, f63, f4 }
        { fmul f103, f65, f85 ; fadd f105, f102, f104 ; fmul f110, f64, f5 }
        { fadd f107, f105, f103 ; fmul f109, f65, f6 ; fadd f111, f108, f110 }
        { fsel f67, r32, f16, f21 ; flw f66, REC_W+64(r11) }
        { flw f30, REC_W+0(r10) ; fsub f93, f94, f92 ; fadd f99, f94, f92 }
        { fsel f67, r33, f67, f21 ; flw f31, REC_W+4(r10) ; fdiv f96, f93, f123 ; fdiv f98, f99, f123 }
        { flt r34, f67, f10 ; flw f32, REC_W+8(r10) ; fadd f113, f111, f109 ; fmov f47, f23 }
        { fsel f12, r34, f20, f12 ; flw f33, REC_W+12(r10) ; movif f20, r11 }
        { flw f34, REC_W+16(r10) }
        { fadd f97, f79, f96 ; fadd f101, f79, f98 ; fmul f114, f96, f113 ; lw r11, 0(r1) }
        { flw f35, REC_W+20(r10) ; fmul f115, f98, f113 ; flt r30, f7, f97 ; flt r37, f7, f101 }
        { fadd f116, f107, f114 ; fadd f117, f107, f115 ; fsel f119, r37, f101, f21 ; addi r1, r1, 4 }
        { flw f36, REC_W+24(r10) ; fsel f90, r30, f97, f21 ; fle r38, f23, f117 ; fle r39, f117, f66 }
        { flw f37, REC_W+28(r10) ; fle r31, f23, f116 ; fle r36, f116, f66 ; fsel f120, r38, f119, f21 }
        { flw f38, REC_W+32(r10) ; fsel f95, r31, f90, f21 ; fsel f122, r39, f120, f21 }
        { fsel f15, r34, f19, f15 ; flw f39, REC_W+36(r10) ; fsel f100, r36, f95, f21 }
        { fsel f10, r34, f67, f10 ; flw f40, REC_W+40(r10) ; fle r40, f100, f122 ; fmin f16, f122, f100 }
        { fsel f13, r34, f17, f13 ; flw f41, REC_W+44(r10) ; fsel f19, r40, f24, f23 }
        { fsel f14, r34, f18, f14 ; fmov f48, f23 ; fmov f49, f24 ; jr r13 }

sph1_B:
        { lw r14, REC_CODE(r10) ; fsub f71, f1, f50 ; fsub f72, f2, f51 ; fsub f73, f3, f52 }
        { lw r13, IC_JUMPS_A(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f53, f4 ; fmul f87, f56, f5 }
        { fadd f78, f77, f76 ; fmul f91, f56, f4 ; fmul f92, f54, f5 }
        { fneg f79, f78 ; fmul f88, f58, f6 ; fadd f89, f86, f87 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f53, f81 ; fmul f102, f56, f83 ; fmul f107, f56, f81 }
        { fmul f103, f58, f85 ; fadd f104, f101, f102 ; fmul f108, f54, f83 }
        { fmul f109, f57, f85 ; fadd f110, f107, f108 ; fmul f113, f58, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f57, f83 }
        { fadd f106, f105, f59 ; fmul f115, f55, f85 ; fadd f116, f113, f114 }
        { fmul f93, f57, f6 ; fadd f112, f111, f60 ; fadd f117, f116, f115 }
        { fadd f94, f91, f92 ; fmul f96, f58, f4 ; fmul f97, f57, f5 }
        { fadd f118, f117, f61 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fle r32, f23, f47 ; flw f30, REC_W+0(r10) ; fmul f80, f59, f81 ; fmul f72, f60, f83 }
        { fadd f90, f89, f88 ; fadd f95, f94, f93 ; fmul f98, f55, f6 }
        { fadd f99, f96, f97 ; fmul f76, f85, f118 ; fadd f78, f75, f77 }
        { fle r33, f48, f49 ; flw f31, REC_W+4(r10) ; fmul f82, f61, f85 ; fadd f73, f80, f72 }
        { fadd f100, f99, f98 ; fmul f119, f4, f90 ; fmul f120, f5, f95 }
        { fmul f124, f4, f106 ; fmul f125, f5, f112 ; fadd f71, f78, f76 }
        { flw f32, REC_W+8(r10) ; fmul f121, f6, f100 ; fadd f84, f73, f82 }
        { flw f62, REC_W+48(r11) ; fadd f122, f119, f120 ; fmul f126, f6, f118 }
        { flw f33, REC_W+12(r10) ; fadd f127, f124, f125 ; fadd f86, f71, f84 }
        { fadd f123, f122, f121 ; fadd f74, f127, f126 ; fadd f87, f86, f62 }
        { flw f34, REC_W+16(r10) ; fmul f89, f74, f74 ; fmul f88, f123, f87 }
        { flw f35, REC_W+20(r10) ; fsub f91, f89, f88 ; fneg f94, f74 }
        { fsel f67, r32, f16, f21 ; flw f36, REC_W+24(r10) ; fsqrt f92, f91 ; fmov f47, f23 }
        { fsel f67, r33, f67, f21 ; flw f37, REC_W+28(r10) ; fmov f48, f28 }
        { flt r34, f67, f10 ; flw f38, REC_W+32(r10) }
        { fsel f12, r34, f20, f12 ; flw f39, REC_W+36(r10) }
        { flw f40, REC_W+40(r10) ; movif f20, r11 ; fsub f93, f94, f92 }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; flw f41, REC_W+44(r10) ; fdiv f96, f93, f123 }
        { fsel f14, r34, f18, f14 ; fsel f15, r34, f19, f15 ; fmov f19, f24 ; lw r11, 0(r1) }
        { addi r1, r1, 4 }
        nop
        { fadd f16, f79, f96 ; fadd f49, f79, f96 ; jr r13 }

sph2_B:
        { lw r14, REC_CODE(r10) ; fsub f71, f1, f50 ; fsub f72, f2, f51 ; fsub f73, f3, f52 }
        { lw r13, IC_JUMPS_A(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fadd f77, f74, f75 ; fmul f86, f53, f4 ; fmul f87, f56, f5 }
        { fadd f78, f77, f76 ; fmul f91, f56, f4 ; fmul f92, f54, f5 }
        { fneg f79, f78 ; fmul f88, f58, f6 ; fadd f89, f86, f87 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f101, f53, f81 ; fmul f102, f56, f83 ; fmul f107, f56, f81 }
        { fmul f103, f58, f85 ; fadd f104, f101, f102 ; fmul f108, f54, f83 }
        { fmul f109, f57, f85 ; fadd f110, f107, f108 ; fmul f113, f58, f81 }
        { fadd f105, f104, f103 ; fadd f111, f110, f109 ; fmul f114, f57, f83 }
        { fadd f106, f105, f59 ; fmul f115, f55, f85 ; fadd f116, f113, f114 }
        { fmul f93, f57, f6 ; fadd f112, f111, f60 ; fadd f117, f116, f115 }
        { fadd f94, f91, f92 ; fmul f96, f58, f4 ; fmul f97, f57, f5 }
        { fadd f118, f117, f61 ; fmul f75, f81, f106 ; fmul f77, f83, f112 }
        { fadd f90, f89, f88 ; fmul f80, f59, f81 ; fmul f72, f60, f83 }
        { fadd f95, f94, f93 ; fmul f98, f55, f6 ; fadd f99, f96, f97 }
        { fmul f76, f85, f118 ; fadd f78, f75, f77 ; fmul f82, f61, f85 }
        { fadd f100, f99, f98 ; fmul f119, f4, f90 ; fadd f73, f80, f72 }
        { fmul f120, f5, f95 ; fmul f124, f4, f106 ; fmul f125, f5, f112 }
        { fle r32, f23, f47 ; flw f62, REC_W+48(r11) ; fadd f71, f78, f76 ; fadd f84, f73, f82 }
        { fmul f121, f6, f100 ; fadd f122, f119, f120 ; fmul f126, f6, f118 }
        { fadd f123, f122, f121 ; fadd f127, f124, f125 ; fadd f86, f71, f84 }
        { fle r33, f48, f49 ; flw f30, REC_W+0(r10) ; fadd f74, f127, f126 ; fadd f87, f86, f62 }
        { flw f31, REC_W+4(r10) ; fmul f89, f74, f74 ; fmul f88, f123, f87 }
        { flw f32, REC_W+8(r10) ; fsub f91, f89, f88 ; fneg f94, f74 }
        { fsel f67, r32, f16, f21 ; flw f33, REC_W+12(r10) ; fsqrt f92, f91 ; fmov f47, f23 }
        { fsel f67, r33, f67, f21 ; flw f34, REC_W+16(r10) ; fmov f48, f23 }
        { flt r34, f67, f10 ; flw f35, REC_W+20(r10) ; fmov f49, f24 }
        { fsel f12, r34, f20, f12 ; flw f36, REC_W+24(r10) }
        { flw f37, REC_W+28(r10) ; fsub f93, f94, f92 ; fadd f99, f94, f92 }
        { flw f38, REC_W+32(r10) ; movif f20, r11 ; fdiv f96, f93, f123 ; fdiv f98, f99, f123 }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; flw f39, REC_W+36(r10) }
        { fsel f14, r34, f18, f14 ; fsel f15, r34, f19, f15 ; flw f40, REC_W+40(r10) }
        { flw f41, REC_W+44(r10) }
        { fadd f97, f79, f96 ; fadd f101, f79, f98 ; lw r11, 0(r1) }
        { flt r30, f7, f97 ; flt r37, f7, f101 }
        { fsel f102, r30, f97, f21 ; fsel f104, r37, f101, f21 ; addi r1, r1, 4 }
        { fle r40, f102, f104 ; fmin f16, f104, f102 }
        { fsel f19, r40, f24, f23 ; jr r13 }

ball1_B:
        { lw r14, REC_CODE(r10) ; fsub f71, f1, f50 ; fsub f72, f2, f51 ; fsub f73, f3, f52 }
        { lw r13, IC_JUMPS_A(r14) ; fmul f74, f71, f4 ; fmul f75, f72, f5 ; fmul f76, f73, f6 }
        { fle r32, f23, f47 ; flw f30, REC_W+0(r10) ; fadd f77, f74, f75 ; fmul f86, f4, f4 }
        { fle r33, f48, f49 ; flw f31, REC_W+4(r10) ; fadd f78, f77, f76 ; fmul f87, f5, f5 }
        { flw f32, REC_W+8(r10) ; fneg f79, f78 ; fmul f88, f6, f6 }
        { fmul f80, f79, f4 ; fmul f82, f79, f5 ; fmul f84, f79, f6 }
        { fadd f81, f71, f80 ; fadd f83, f72, f82 ; fadd f85, f73, f84 }
        { fmul f91, f4, f81 ; fmul f96, f81, f81 ; fmul f97, f83, f83 }
        { fmul f92, f5, f83 ; fmul f98, f85, f85 ; fadd f99, f96, f97 }
        { flw f62, REC_W+48(r11) ; fadd f89, f86, f87 ; fmul f93, f6, f85 }
        { flw f33, REC_W+12(r10) ; fadd f94, f91, f92 ; fadd f100, f99, f98 }
        { fadd f90, f89, f88 ; fadd f95, f94, f93 ; fadd f101, f100, f62 }
        { flw f34, REC_W+16(r10) ; fmul f102, f95, f95 ; fmul f103, f90, f101 }
        { flw f35, REC_W+20(r10) ; fsub f104, f102, f103 ; fneg f106, f95 }
        { fsel f67, r32, f16, f21 ; flw f36, REC_W+24(r10) ; fsqrt f105, f104 ; fmov f47, f23 }
        { fsel f67, r33, f67, f21 ; flw f37, REC_W+28(r10) ; fmov f48, f28 }
        { flt r34, f67, f10 ; flw f38, REC_W+32(r10) }
        { fsel f12, r34, f20, f12 ; flw f39, REC_W+36(r10) }
        { flw f40, REC_W+40(r10) ; movif f20, r11 ; fsub f107, f106, f105 }
        { fsel f10, r34, f67, f10 ; fsel f13, r34, f17, f13 ; flw f41, REC_W+44(r10) ; fdiv f108, f107, f90 }
        { fsel f14, r34, f18, f14 ; fsel f15, r34, f19, f15 ; fmov f19, f24 ; lw r11, 0(r1) }
        { addi r1, r1, 4 }
        nop
        { fadd f16, f79, f108 ; fadd f49, f79, f108 ; jr r13 }
