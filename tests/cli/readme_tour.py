#!/usr/bin/env python3
"""The README's tour stays true: each ``` block whose first line is `$ build/nesshi ...` (or
`$ mpirun ... build/nesshi ...`, when mpirun is installed) is run
(in a scratch folder that links the checkout's examples/, tests/, kernels/ and the nesshi under
test as build/nesshi) and what it prints (stdout and stderr) must match the block's other lines.
A line `...` in the block stands for any number of lines; wall times (`0.42 s`, `87.2 M
bundles/s`, `1:05`) are masked, and /tmp/ paths are the scratch folder's. Usage: readme_tour.py README NESSHI ROOT"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

TIMES = [re.compile(p) for p in (r'\d+(\.\d+)? ?(s|ms)\b', r'\d+(\.\d+)? M bundles/s', r'\b\d+:\d\d\b', r'\(\d+ threads?\)',
                                  r'\[\d+/')]  # the order in which parallel cells finish
SKIP = ('nesshi debug',)  # interactive: its session is a golden test (tests/cli/iss)
HAVE_MPIRUN = shutil.which('mpirun') is not None
# OpenMPI refuses root (CI containers) unless told, and more ranks than cores unless told.
MPI_ENV = {'OMPI_ALLOW_RUN_AS_ROOT': '1', 'OMPI_ALLOW_RUN_AS_ROOT_CONFIRM': '1', 'OMPI_MCA_rmaps_base_oversubscribe': '1'}


def tour_block(first):
    return first.startswith('$ build/nesshi ') or (HAVE_MPIRUN and re.match(r'\$ mpirun .* build/nesshi ', first))


def mask(line):
    for p in TIMES:
        line = p.sub('<t>', line)
    return line.rstrip()


def matches(want, got):
    """`...` in want matches any run of lines."""
    if not want:
        return not got
    if want[0] == '...':
        return any(matches(want[1:], got[k:]) for k in range(len(got) + 1))
    return bool(got) and mask(want[0]) == mask(got[0]) and matches(want[1:], got[1:])


def commands(text):
    """(line, command, expected lines) for each `$ ` line of a block that starts with one."""
    lines = text.split('\n')
    i = 0
    while i < len(lines):
        if lines[i].startswith('```') and i + 1 < len(lines) and tour_block(lines[i + 1]):
            j = i + 1
            while not lines[j].startswith('```'):
                k = j + 1
                while not lines[k].startswith('```') and not lines[k].startswith('$ '):
                    k += 1
                yield j + 1, lines[j][2:], lines[j + 1:k]
                j = k
            i = j
        i += 1


def main():
    readme, nesshi, root = sys.argv[1:4]
    failed = 0
    with tempfile.TemporaryDirectory() as work:
        for d in ('examples', 'tests', 'kernels'):
            os.symlink(os.path.join(root, d), os.path.join(work, d))
        os.mkdir(os.path.join(work, 'build'))
        os.symlink(os.path.abspath(nesshi), os.path.join(work, 'build', 'nesshi'))
        for line, cmd, want in commands(open(readme).read()):
            if any(s in cmd for s in SKIP):
                continue
            # /tmp/ paths in the tour go to the scratch folder: a rerun starts from nothing
            run = cmd.replace('/tmp/', work + '/')
            r = subprocess.run(['bash', '-c', run + ' 2>&1'], cwd=work, capture_output=True, text=True, timeout=600,
                               env={**os.environ, **MPI_ENV})
            out = r.stdout.rstrip('\n').replace(work + '/', '/tmp/')
            got = out.split('\n') if out else []  # a command that prints nothing
            if matches(want, got):
                print(f'README.md:{line}: ok: {cmd}')
                continue
            failed += 1
            print(f'README.md:{line}: error: `{cmd}` prints something else; it printed:')
            print('\n'.join(got))
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
