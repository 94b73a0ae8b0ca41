#!/usr/bin/env python3
"""pack.py: list-schedules straight-line blocks of a kernel into bundles (a development aid).

Input: a .s file whose straight-line blocks are written one operation per line between
`#pack begin` and `#pack end` lines (sequential semantics, in dependence order). Each block is
replaced, in the output, by bundles that respect the machine's units, register-file ports and
exposed latencies (RAW, WAR, WAW), keeping FIFO words of one channel and memory accesses in
order; a final branch stays last. Everything outside the markers is copied unchanged.
The hand-scheduled loops are *not* produced by this tool: they are written and explained by
hand. Usage: pack.py -m os|ic|seq IN.pack.s > OUT.s
"""
import re
import sys

MACHINES = {
    'os': dict(names=['iu0', 'iu1', 'fpu0', 'fpu1'], units=[{'alu', 'mul', 'load', 'store', 'branch', 'fifo', 'misc'},
                      {'alu', 'mul', 'load', 'store', 'fifo', 'misc'},
                      {'fadd', 'fmul', 'fdiv', 'fifo', 'misc'},
                      {'fadd', 'fmul', 'fdiv', 'fifo', 'misc'}],
               rp={'r': 5, 'f': 5}, wp={'r': 2, 'f': 2}),
    'ic': dict(names=['iu0', 'fpu0', 'fpu1', 'fpu2'], units=[{'alu', 'mul', 'load', 'store', 'branch', 'fifo', 'misc'},
                      {'fadd', 'fmul', 'fdiv', 'fifo', 'misc'},
                      {'fadd', 'fmul', 'fdiv', 'fifo', 'misc'},
                      {'fadd', 'fmul', 'fdiv', 'fifo', 'misc'}],
               rp={'r': 5, 'f': 7}, wp={'r': 2, 'f': 3}),
    'seq': dict(names=['u0'], units=[{'alu', 'mul', 'fadd', 'fmul', 'fdiv', 'load', 'store', 'branch', 'fifo', 'misc'}],
                rp={'r': 3, 'f': 3}, wp={'r': 1, 'f': 1}),
}
LAT = {'fdiv': 4}

CLASS = {}
for m in 'add sub and or xor sll srl sra slt sltu seq sne min max addi andi ori xori slli srli srai slti li mov sel'.split():
    CLASS[m] = 'alu'
CLASS['mul'] = 'mul'
for m in 'fadd fsub fmin fmax fabs fneg fmov fli fsel flt fle feq itof ftoi movif movfi'.split():
    CLASS[m] = 'fadd'
CLASS['fmul'] = 'fmul'
CLASS['fdiv'] = CLASS['fsqrt'] = 'fdiv'
for m in 'lw lh lhu lb lbu flw'.split():
    CLASS[m] = 'load'
for m in 'sw sh sb fsw'.split():
    CLASS[m] = 'store'
for m in 'beq bne blt bge bltu bgeu beqz bnez jmp jal jr'.split():
    CLASS[m] = 'branch'
for m in 'recv frecv send fsend'.split():
    CLASS[m] = 'fifo'
CLASS['nop'] = CLASS['halt'] = 'misc'
NODEST = set('sw sh sb fsw beq bne blt bge bltu bgeu beqz bnez jmp jr send fsend nop halt'.split())
REG = re.compile(r'\b([rf])(\d+)\b')


class Op:
    def __init__(self, text):
        self.text = text.strip()
        mnem, _, rest = self.text.partition(' ')
        self.mnem = mnem
        self.cls = CLASS[mnem]
        args = [a.strip() for a in rest.split(',')] if rest.strip() else []
        self.dst = None
        srcs = args
        if mnem not in NODEST and args and REG.fullmatch(args[0]):
            self.dst = args[0]
            srcs = args[1:]
        self.srcs = [m.group(0) for a in srcs for m in REG.finditer(a)]
        self.lat = LAT.get(self.cls, 1)
        self.chan = None
        if self.cls == 'fifo':
            self.chan = args[1] if mnem in ('recv', 'frecv') else args[0]


def schedule(ops, mach):
    """Critical-path list scheduling of one straight-line block (a final branch stays last)."""
    units, rp, wp = mach['units'], mach['rp'], mach['wp']
    n = len(ops)
    preds = [[] for _ in range(n)]   # (i, distance): c_j >= c_i + distance
    last_w, readers, last_store, loads, chan_last = {}, {}, None, [], {}
    for j, op in enumerate(ops):
        for s_ in op.srcs:
            if s_ in last_w:
                i = last_w[s_]
                preds[j].append((i, ops[i].lat))
        if op.dst:
            d = op.dst
            for i in readers.get(d, []):
                if i != j:
                    preds[j].append((i, 1 - op.lat))
            if d in last_w:
                i = last_w[d]
                preds[j].append((i, ops[i].lat + 1 - op.lat))
        if op.cls == 'load' and last_store is not None:
            preds[j].append((last_store, 1))
        if op.cls == 'store':
            for i in loads:
                preds[j].append((i, 0))
            if last_store is not None:
                preds[j].append((last_store, 1))
        if op.chan is not None and op.chan in chan_last:
            preds[j].append((chan_last[op.chan], 0))
        if op.cls in ('branch', 'misc') and op.mnem != 'nop':
            for i in range(j):
                preds[j].append((i, max(ops[i].lat - 1, 0)))
        # bookkeeping
        for s_ in op.srcs:
            readers.setdefault(s_, []).append(j)
        if op.dst:
            last_w[op.dst] = j
            readers[op.dst] = []
        if op.cls == 'load':
            loads.append(j)
        if op.cls == 'store':
            last_store = j
            loads = []
        if op.chan is not None:
            chan_last[op.chan] = j
    succs = [[] for _ in range(n)]
    for j in range(n):
        for i, d in preds[j]:
            succs[i].append((j, d))
    height = [0] * n
    for i in reversed(range(n)):
        h = ops[i].lat
        for j, d in succs[i]:
            h = max(h, d + height[j])
        height[i] = h
    # ops that only the scarcest unit kind accepts are also prioritised by how many follow them
    def only_int(op):
        return all(op.cls not in u or 'fadd' not in u for u in units) and len(units) > 1
    remaining = 0
    prio = [0] * n
    for i in reversed(range(n)):
        p_ = height[i]
        if only_int(ops[i]):
            remaining += 1
            p_ = max(p_, remaining + 1)
        for j, d in succs[i]:
            p_ = max(p_, d + prio[j])
        prio[i] = p_
    cyc_of = [None] * n
    cyc, reads, writes = [], [], {}
    done = 0
    c = 0
    progress = True
    while done < n:
        while len(cyc) <= c:
            cyc.append([])
            reads.append({'r': 0, 'f': 0})
        if not progress:
            c += 1
            progress = True
            continue
        progress = False
        ready = []
        for j in range(n):
            if cyc_of[j] is not None:
                continue
            if all(cyc_of[i] is not None and cyc_of[i] + d <= c for i, d in preds[j]):
                if ops[j].cls == 'branch' and done != n - 1:
                    continue
                ready.append(j)
        ready.sort(key=lambda j: (-prio[j], j))
        for j in ready:
            op = ops[j]
            op.index = j
            if assign(sorted(cyc[c] + [op], key=lambda o: o.index), units) is None:
                continue
            rr = dict(reads[c])
            for s_ in op.srcs:
                rr[s_[0]] += 1
            if any(rr[k] > rp[k] for k in rr):
                continue
            if op.dst:
                w = writes.get(c + op.lat, {'r': 0, 'f': 0})
                if w[op.dst[0]] + 1 > wp[op.dst[0]]:
                    continue
            # a same-cycle predecessor with distance 0 must precede in the bundle: keep program order
            cyc[c].append(op)
            op.index = j
            reads[c] = rr
            if op.dst:
                w = writes.setdefault(c + op.lat, {'r': 0, 'f': 0})
                w[op.dst[0]] += 1
            cyc_of[j] = c
            done += 1
            progress = True
    end = max(cyc_of[j] + ops[j].lat for j in range(n)) if n else 0
    last = ops[-1] if n else None
    if not (last and last.cls == 'branch'):
        while len(cyc) < end:
            cyc.append([])
    while cyc and not cyc[-1]:
        cyc.pop()
    for b_ in cyc:
        b_.sort(key=lambda o: o.index)
    return cyc


def assign(ops, units):
    """Slots for ops (in program order) such that FIFO words keep program order: the ISS moves
    a bundle's FIFO words in slot order. Returns a slot index per op, or None."""
    import itertools
    for perm in itertools.permutations(range(len(units)), len(ops)):
        if any(o.cls not in units[u] for o, u in zip(ops, perm)):
            continue
        fifo = [u for o, u in zip(ops, perm) if o.cls == 'fifo']
        if fifo != sorted(fifo):
            continue
        return perm
    return None


def match(classes, units):
    used = [False] * len(units)

    def go(i):
        if i == len(classes):
            return True
        for u in range(len(units)):
            if not used[u] and classes[i] in units[u]:
                used[u] = True
                if go(i + 1):
                    return True
                used[u] = False
        return False
    return go(0)


def main():
    args = sys.argv[1:]
    mach = MACHINES[args[args.index('-m') + 1]]
    path = args[-1]
    out = []
    block = None
    indent = '        '
    for line in open(path):
        s = line.rstrip('\n')
        if s.strip().startswith('#pack begin'):
            block = []
            continue
        if s.strip().startswith('#pack end'):
            cyc = schedule(block, mach)
            for ops in cyc:
                if not ops:
                    out.append(indent + 'nop')
                    continue
                perm = assign(ops, mach['units'])
                fifo = any(o.cls == 'fifo' for o in ops) and len(ops) > 1
                texts = [('%s: %s' % (mach['names'][u], o.text)) if fifo else o.text
                         for u, o in sorted(zip(perm, ops), key=lambda t: t[0] if fifo else 0)]
                out.append(indent + '{ ' + ' ; '.join(texts) + ' }')
            block = None
            continue
        if block is not None:
            t = s.split('#')[0].strip()
            if t:
                block.append(Op(t))
            continue
        out.append(s)
    print('\n'.join(out))


if __name__ == '__main__':
    main()
