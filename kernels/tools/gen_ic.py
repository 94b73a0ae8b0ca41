#!/usr/bin/env python3
"""gen_ic.py: prints intersect.pk, the IC kernel's source before `nesshi schedule` bundles it.

build.sh keeps that intermediate out of the tree (a temporary or build directory) and commits
only kernels/ic/intersect.s.

The kernel has eight primitive bodies: {one-sided, two-sided} x {triangle, quadric} x {A, B}.
Body X processes primitive m from payload buffer X (already loaded), and at the same time
  - finishes primitive m-1 (the kind-independent *accept tail*: range test, closest-hit update),
  - prefetches primitive m+1 (dispatch code, jump target, first 12 payload words into buffer Y),
  - loads the list entry of primitive m+2,
then jumps (jr) to the body of m+1's kind in variant Y. The bodies are straight-line code, so
`nesshi schedule` list-schedules each one; their overlap across primitives is this hand-made software
pipeline (three primitives in flight: m+1 loading, m computing, m-1 being accepted).
"""

BUF = {'A': 30, 'B': 50}      # payload buffers f30..f46 / f50..f66
BASE = {'A': 'r10', 'B': 'r11'}
JT = {'A': 'IC_JUMPS_A', 'B': 'IC_JUMPS_B'}
OTHER = {'A': 'B', 'B': 'A'}

# fixed float registers
O = ['f1', 'f2', 'f3']
D = ['f4', 'f5', 'f6']
TMIN, TMAX, TOUT = 'f7', 'f8', 'f9'
BOUND, BEST_T, BEST_REC, BEST_U, BEST_V, BEST_FRONT = 'f10', 'f11', 'f12', 'f13', 'f14', 'f15'
CAND_T, CAND_U, CAND_V, CAND_FRONT, CAND_REC = 'f16', 'f17', 'f18', 'f19', 'f20'
INF, NINF, ZERO, ONE = 'f21', 'f22', 'f23', 'f24'
TMINUP = 'f28'  # the float just above tmin (tmin >= 0): t > tmin <=> tmin_up <= t
CP, CQ = 'r32', 'r33'   # candidate flags, computed and applied by the tail
CPV, CQA, CQB = 'f47', 'f48', 'f49'  # the head's values for them: 0 <= CPV, CQA <= CQB
SHADOW = 'r23'


def w(x, i):
    return 'f%d' % (BUF[x] + i)


class Tmp:
    """Virtual float temporaries (%vN); assign() maps them to f71..f127 by linear scan."""
    def __init__(self):
        self.n = 0

    def f(self):
        self.n += 1
        return '%%v%d' % self.n


def assign(ops):
    import re
    pat = re.compile(r'%v\d+')
    last = {}
    for i, op in enumerate(ops):
        for v in pat.findall(op):
            last[v] = i
    free = ['f%d' % r for r in range(71, 128)]
    phys = {}
    out = []
    for i, op in enumerate(ops):
        names = pat.findall(op)
        if not names:
            out.append(op)
            continue
        mnem, _, rest = op.partition(' ')
        args = [a.strip() for a in rest.split(',')]
        dst = args[0] if args and args[0].startswith('%v') and mnem not in ('fsw', 'fsend') else None
        srcs = [a for a in args[1:] if a.startswith('%v')] if dst else [a for a in args if a.startswith('%v')]
        for v in srcs:
            assert v in phys, (v, op)
        mapped = {v: phys[v] for v in srcs}
        for v in dict.fromkeys(srcs):
            if last[v] == i:
                free.append(phys.pop(v))
        if dst:
            if dst not in phys:
                phys[dst] = free.pop(0)
            mapped[dst] = phys[dst]
        out.append(pat.sub(lambda mm: mapped[mm.group(0)], op))
    return out


def tail():
    """Accept the candidate of the previous primitive (kind-independent): mask it with the
    head's two deferred flags, compare it with the bound, and keep it when it is nearer."""
    return [
        '# accept tail of the previous primitive',
        'fle %s, %s, %s' % (CP, ZERO, CPV),
        'fle %s, %s, %s' % (CQ, CQA, CQB),
        'fsel f67, %s, %s, %s' % (CP, CAND_T, INF),
        'fsel f67, %s, f67, %s' % (CQ, INF),
        'flt r34, f67, %s' % BOUND,
        'fsel %s, r34, f67, %s' % (BOUND, BOUND),
        'fsel %s, r34, %s, %s' % (BEST_REC, CAND_REC, BEST_REC),
        'fsel %s, r34, %s, %s' % (BEST_U, CAND_U, BEST_U),
        'fsel %s, r34, %s, %s' % (BEST_V, CAND_V, BEST_V),
        'fsel %s, r34, %s, %s' % (BEST_FRONT, CAND_FRONT, BEST_FRONT),
    ]


def prefetch(x):
    y = OTHER[x]
    by = BASE[y]
    out = ['# prefetch primitive m+1: dispatch target, payload words 0..11 into buffer ' + y,
           'lw r14, REC_CODE(%s)' % by,
           'lw r13, %s(r14)' % JT[y]]
    for i in range(12):
        out.append('flw %s, REC_W+%d(%s)' % (w(y, i), 4 * i, by))
    return out


def next_entry(x):
    return ['# list entry of primitive m+2',
            'lw %s, 0(r1)' % BASE[x],
            'addi r1, r1, 4']


def tri(x, two):
    t = Tmp()
    m = lambda: t.f()
    o = []
    X = lambda i: w(x, i)
    o.append('# triangle (%s-sided): plane-equation method, twin operation order' % ('two' if two else 'one'))
    a0, a1, a2 = m(), m(), m()
    o += ['fmul %s, %s, %s' % (a0, X(0), D[0]), 'fmul %s, %s, %s' % (a1, X(1), D[1]),
          'fmul %s, %s, %s' % (a2, X(2), D[2])]
    s1, dn = m(), m()
    o += ['fadd %s, %s, %s' % (s1, a0, a1), 'fadd %s, %s, %s' % (dn, s1, a2)]
    b0, b1, b2 = m(), m(), m()
    o += ['fmul %s, %s, %s' % (b0, X(0), O[0]), 'fmul %s, %s, %s' % (b1, X(1), O[1]),
          'fmul %s, %s, %s' % (b2, X(2), O[2])]
    s2, s3, on = m(), m(), m()
    o += ['fadd %s, %s, %s' % (s2, b0, b1), 'fadd %s, %s, %s' % (s3, s2, b2), 'fadd %s, %s, %s' % (on, s3, X(3))]
    non, tt = m(), m()
    o += ['fneg %s, %s' % (non, on), 'fdiv %s, %s, %s' % (tt, non, dn)]
    p = []
    for k in range(3):
        mk, pk = m(), m()
        o += ['fmul %s, %s, %s' % (mk, tt, D[k]), 'fadd %s, %s, %s' % (pk, O[k], mk)]
        p.append(pk)
    res = []
    for r, dst in ((4, CAND_U), (8, CAND_V)):
        c0, c1, c2, u1, u2 = m(), m(), m(), m(), m()
        o += ['fmul %s, %s, %s' % (c0, X(r), p[0]), 'fmul %s, %s, %s' % (c1, X(r + 1), p[1]),
              'fmul %s, %s, %s' % (c2, X(r + 2), p[2]),
              'fadd %s, %s, %s' % (u1, c0, c1), 'fadd %s, %s, %s' % (u2, u1, c2),
              'fadd %s, %s, %s' % (dst, u2, X(r + 3))]
    tm = m()
    o += ['fadd %s, %s, %s' % (CQA, CAND_U, CAND_V)]
    if two:
        o += ['feq r30, %s, %s' % (dn, ZERO), 'fsel %s, r30, %s, %s' % (tm, INF, tt)]
    else:
        o += ['flt r30, %s, %s' % (dn, ZERO), 'fsel %s, r30, %s, %s' % (tm, tt, INF)]
    o += ['flt r31, %s, %s' % (TMIN, tt), 'fsel %s, r31, %s, %s' % (CAND_T, tm, INF),
          'fmin %s, %s, %s' % (CPV, CAND_U, CAND_V), 'fmov %s, %s' % (CQB, ONE),
          'movif %s, %s' % (CAND_REC, BASE[x])]
    return o


def quad(x, two, sphere=False, ball=False):
    t = Tmp()
    m = lambda: t.f()
    o = []
    X = lambda i: w(x, i)
    o.append('# quadric (%s-sided%s): general quadric form, twin operation order'
             % ('two' if two else 'one', ', no axial clip' if sphere else ''))
    for i in range(12, 13 if sphere else 17):
        if ball and i != 12:
            continue
        o.append('flw %s, REC_W+%d(%s)' % (X(i) if i < 16 or two else CQB, 4 * i, BASE[x]))
    o.append('movif %s, %s' % (CAND_REC, BASE[x]))
    P = []
    for k in range(3):
        pk = m()
        o.append('fsub %s, %s, %s' % (pk, O[k], X(k)))
        P.append(pk)

    def dot3(u, v, add=None):
        c0, c1, c2, s1, s2 = m(), m(), m(), m(), m()
        r = ['fmul %s, %s, %s' % (c0, u[0], v[0]), 'fmul %s, %s, %s' % (c1, u[1], v[1]),
             'fmul %s, %s, %s' % (c2, u[2], v[2]), 'fadd %s, %s, %s' % (s1, c0, c1), 'fadd %s, %s, %s' % (s2, s1, c2)]
        if add is None:
            return r, s2
        s3 = m()
        return r + ['fadd %s, %s, %s' % (s3, s2, add)], s3

    r, pd = dot3(P, D)
    t0 = m()
    o += r + ['fneg %s, %s' % (t0, pd)]
    Q = []
    for k in range(3):
        mk, qk = m(), m()
        o += ['fmul %s, %s, %s' % (mk, t0, D[k]), 'fadd %s, %s, %s' % (qk, P[k], mk)]
        Q.append(qk)
    A, B, C, Dh, Eh, Fh, Gh, Hh, Ih, J = (X(i) for i in range(3, 13))
    if ball:
        # M = I, g = 0: Md = d and Mq + g/2 = q exactly (see kernels/image.hpp, plain_sphere)
        r, qa = dot3(D, D)
        o += r
        r, qb = dot3(D, Q)
        o += r
        r, qq = dot3(Q, Q)
        o += r
        qc = m()
        o += ['fadd %s, %s, %s' % (qc, qq, J)]
        return finish_roots(o, m, x, two, sphere, qa, qb, qc, t0, Q, X)
    rows = [(A, Dh, Fh), (Dh, B, Eh), (Fh, Eh, C)]
    MD = []
    for row in rows:
        r, v = dot3(row, D)
        o += r
        MD.append(v)
    MQ = []
    for row, g in zip(rows, (Gh, Hh, Ih)):
        r, v = dot3(row, Q, g)
        o += r
        MQ.append(v)
    r, qa = dot3(D, MD)
    o += r
    r, qb = dot3(D, MQ)
    o += r
    r, qq = dot3(Q, MQ)
    o += r
    r, gq = dot3((Gh, Hh, Ih), Q)
    o += r
    c1, qc = m(), m()
    o += ['fadd %s, %s, %s' % (c1, qq, gq), 'fadd %s, %s, %s' % (qc, c1, J)]
    return finish_roots(o, m, x, two, sphere, qa, qb, qc, t0, Q, X)


def finish_roots(o, m, x, two, sphere, qa, qb, qc, t0, Q, X):
    D = globals()['D']

    def dot3(u, v):
        c0, c1, c2, s1, s2 = m(), m(), m(), m(), m()
        return ['fmul %s, %s, %s' % (c0, u[0], v[0]), 'fmul %s, %s, %s' % (c1, u[1], v[1]),
                'fmul %s, %s, %s' % (c2, u[2], v[2]), 'fadd %s, %s, %s' % (s1, c0, c1),
                'fadd %s, %s, %s' % (s2, s1, c2)], s2
    bb, ac, disc, rr, nb = m(), m(), m(), m(), m()
    o += ['fmul %s, %s, %s' % (bb, qb, qb), 'fmul %s, %s, %s' % (ac, qa, qc), 'fsub %s, %s, %s' % (disc, bb, ac),
          'fsqrt %s, %s' % (rr, disc), 'fneg %s, %s' % (nb, qb)]
    n1, sf = m(), m()
    o += ['fsub %s, %s, %s' % (n1, nb, rr), 'fdiv %s, %s, %s' % (sf, n1, qa)]
    tf = m()
    if sphere and not two:
        # the root goes straight to the candidate; its range test t > tmin becomes the tail's
        # non-strict CQA <= CQB as tmin_up <= t (tmin_up = the float above tmin, made per ray)
        o += ['fadd %s, %s, %s' % (CAND_T, t0, sf), 'fadd %s, %s, %s' % (CQB, t0, sf),
              'fmov %s, %s' % (CPV, ZERO), 'fmov %s, %s' % (CQA, TMINUP), 'fmov %s, %s' % (CAND_FRONT, ONE)]
        return o
    o += ['fadd %s, %s, %s' % (tf, t0, sf)]
    if two:
        n2, sb, tb = m(), m(), m()
        o += ['fadd %s, %s, %s' % (n2, nb, rr), 'fdiv %s, %s, %s' % (sb, n2, qa), 'fadd %s, %s, %s' % (tb, t0, sb)]
    if sphere:
        if not two:
            o += ['flt r30, %s, %s' % (TMIN, tf), 'fsel %s, r30, %s, %s' % (CAND_T, tf, INF),
                  'fmov %s, %s' % (CPV, ZERO), 'fmov %s, %s' % (CQA, ZERO), 'fmov %s, %s' % (CQB, ONE),
                  'fmov %s, %s' % (CAND_FRONT, ONE)]
        else:
            ef, eb = m(), m()
            o += ['flt r30, %s, %s' % (TMIN, tf), 'fsel %s, r30, %s, %s' % (ef, tf, INF),
                  'flt r37, %s, %s' % (TMIN, tb), 'fsel %s, r37, %s, %s' % (eb, tb, INF),
                  'fle r40, %s, %s' % (ef, eb), 'fmin %s, %s, %s' % (CAND_T, eb, ef),
                  'fsel %s, r40, %s, %s' % (CAND_FRONT, ONE, ZERO),
                  'fmov %s, %s' % (CPV, ZERO), 'fmov %s, %s' % (CQA, ZERO), 'fmov %s, %s' % (CQB, ONE)]
        return o
    r, aq = dot3((X(13), X(14), X(15)), Q)
    o += r
    r, ad = dot3((X(13), X(14), X(15)), D)
    o += r
    L = X(16) if two else CQB
    mf = m()
    hf = m() if two else CPV
    o += ['fmul %s, %s, %s' % (mf, sf, ad), 'fadd %s, %s, %s' % (hf, aq, mf)]
    if not two:
        o += ['flt r30, %s, %s' % (TMIN, tf), 'fsel %s, r30, %s, %s' % (CAND_T, tf, INF),
              'fmov %s, %s' % (CQA, CPV),
              'fmov %s, %s' % (CAND_FRONT, ONE)]
    else:
        mb, hb = m(), m()
        o += ['fmul %s, %s, %s' % (mb, sb, ad), 'fadd %s, %s, %s' % (hb, aq, mb)]
        ef1, ef2, ef3, eb1, eb2, eb3 = m(), m(), m(), m(), m(), m()
        o += ['flt r30, %s, %s' % (TMIN, tf), 'fsel %s, r30, %s, %s' % (ef1, tf, INF),
              'fle r31, %s, %s' % (ZERO, hf), 'fsel %s, r31, %s, %s' % (ef2, ef1, INF),
              'fle r36, %s, %s' % (hf, L), 'fsel %s, r36, %s, %s' % (ef3, ef2, INF),
              'flt r37, %s, %s' % (TMIN, tb), 'fsel %s, r37, %s, %s' % (eb1, tb, INF),
              'fle r38, %s, %s' % (ZERO, hb), 'fsel %s, r38, %s, %s' % (eb2, eb1, INF),
              'fle r39, %s, %s' % (hb, L), 'fsel %s, r39, %s, %s' % (eb3, eb2, INF),
              'fle r40, %s, %s' % (ef3, eb3),
              'fmin %s, %s, %s' % (CAND_T, eb3, ef3),
              'fsel %s, r40, %s, %s' % (CAND_FRONT, ONE, ZERO),
              'fmov %s, %s' % (CPV, ZERO), 'fmov %s, %s' % (CQA, ZERO), 'fmov %s, %s' % (CQB, ONE)]
    return o


def body(name, x, head):
    lines = ['%s:' % name, '#pack begin']
    lines += tail()
    lines += prefetch(x)
    lines += assign(head)
    lines += next_entry(x)
    lines += ['jr r13', '#pack end', '']
    return lines


HEADER_TEXT = open(__file__.replace('gen_ic.py', 'ic_header.txt')).read().rstrip('\n')


def main():
    out = ['# machine: ic', HEADER_TEXT, '        .include "../abi.inc"', '        .text', 'start:', '#pack begin']
    out += ['li r0, 0', 'li r60, 0x7f800000', 'li r61, 0xff800000', 'movif %s, r60' % INF, 'movif %s, r61' % NINF,
            'fli %s, 0.0' % ZERO, 'fli %s, 1.0' % ONE, 'lw r20, IC_HEADER+ICH_VOXTAB(r0)']
    for x in 'AB':
        for code, lab in ((0, 'tri1'), (4, 'tri2'), (8, 'quad1'), (12, 'quad2'), (20, 'sph1'), (24, 'sph2'), (28, 'ball1')):
            out += ['li r62, %s_%s' % (lab, x), 'sw r62, %s+%d(r0)' % (JT[x], code)]
        out += ['li r62, done', 'sw r62, %s+16(r0)' % JT[x]]
    out += ['#pack end', '']
    out += ['# ---- receive a VISIT: tag, voxel, t_in, t_out, o, d, tmin, tmax ----',
            'next_ray:', '#pack begin',
            'recv r2, CH_IN', 'recv r3, CH_IN', 'frecv f25, CH_IN', 'frecv %s, CH_IN' % TOUT] + \
           ['frecv %s, CH_IN' % r for r in O + D] + ['frecv %s, CH_IN' % TMIN, 'frecv %s, CH_IN' % TMAX] + [
            'slli r5, r3, 2', 'add r5, r5, r20', 'lw r1, 0(r5)',
            'lw r10, 0(r1)', 'lw r11, 4(r1)', 'addi r1, r1, 8',
            'lw r14, REC_CODE(r10)', 'lw r13, IC_JUMPS_A(r14)'] + \
           ['flw %s, REC_W+%d(r10)' % (w('A', i), 4 * i) for i in range(12)] + [
            '# bound = min(next float above t_out, tmax); shadow rays: tmax (any hit counts)',
            '# r6 = 0 exactly for shadow rays: kind bits == KIND_SHADOW',
            'andi r6, r2, TAG_KIND_MASK << TAG_KIND_SHIFT', 'addi r6, r6, -(KIND_SHADOW << TAG_KIND_SHIFT)',
            'movfi r7, %s' % TOUT, 'addi r7, r7, 1', 'movif f26, r7', 'fmin f27, f26, %s' % TMAX,
            'movfi r8, %s' % TMIN, 'addi r8, r8, 1', 'movif %s, r8' % TMINUP,
            'fsel %s, r6, f27, %s' % (BOUND, TMAX),
            'fmov %s, %s' % (CAND_T, INF), 'fmov %s, %s' % (BEST_REC, ZERO),
            'jr r13', '#pack end', '']
    for x in 'AB':
        out += body('tri1_' + x, x, tri(x, False))
        out += body('tri2_' + x, x, tri(x, True))
        out += body('quad1_' + x, x, quad(x, False))
        out += body('quad2_' + x, x, quad(x, True))
        out += body('sph1_' + x, x, quad(x, False, True))
        out += body('sph2_' + x, x, quad(x, True, True))
        out += body('ball1_' + x, x, quad(x, False, True, True))
    out += ['# ---- end of the list: accept the last candidate, then HIT or RETURN ----', 'done:', '#pack begin']
    out += tail()
    out += ['movfi r7, %s' % BEST_REC, 'bnez r7, hit', '#pack end',
            'return:', '#pack begin', 'send CH_IC_OS, r2', 'jmp next_ray', '#pack end', '',
            'hit:', '#pack begin',
            'li r8, 0x7fffffff', 'and r8, r2, r8', 'lw r9, REC_INDEX(r7)', 'ftoi r12, %s' % BEST_FRONT,
            '# triangles: front = 1; quadrics: u = v = 0 (the bodies do not write what the kind does not use)',
            'lw r15, REC_CODE(r7)', 'slti r16, r15, CODE_QUAD1', 'li r17, 1', 'sel r12, r16, r17, r12',
            'fsel %s, r16, %s, %s' % (BEST_U, BEST_U, ZERO), 'fsel %s, r16, %s, %s' % (BEST_V, BEST_V, ZERO),
            'send CH_IC_SC, r8', 'send CH_IC_SC, r9', 'fsend CH_IC_SC, %s' % BOUND,
            'fsend CH_IC_SC, %s' % BEST_U, 'fsend CH_IC_SC, %s' % BEST_V, 'send CH_IC_SC, r12',
            'jmp next_ray', '#pack end']
    print('\n'.join(('        ' + l) if l and not l.endswith(':') and not l.startswith('#') else l for l in out))


if __name__ == '__main__':
    main()
