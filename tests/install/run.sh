#!/usr/bin/env bash
# tests/install/run.sh BUILD_DIR [PYTHON]: installs the build into a temporary prefix, then builds
# and runs an outside program against it twice (CMake's find_package, then pkg-config), checks
# that the tool, man pages, completion and examples are in place, and, given the Python the module
# was built for, imports the installed module.
set -euo pipefail
build=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
for f in bin/nesshi share/man/man1/nesshi.1 share/man/man1/nesshi-render.1 share/bash-completion/completions/nesshi \
         share/zsh/site-functions/_nesshi share/nesshisen/examples/dot3.s include/nesshisen/iss/processor.hpp; do
  [ -s "$prefix/$f" ] || { echo "not installed: $f"; exit 1; }
done
"$prefix/bin/nesshi" --version

echo "== find_package(Nesshisen)"
cmake -S "$here/consumer" -B "$tmp/cmake-build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$tmp/cmake-build" >/dev/null
"$tmp/cmake-build/consumer"

echo "== pkg-config nesshisen"
libdir=$(dirname "$(find "$prefix" -name nesshisen.pc)")
flags=$(PKG_CONFIG_PATH="$libdir" pkg-config --cflags --libs nesshisen)
expect_compiled=0
case "$flags" in *-lnesshi_compiled_runs*) expect_compiled=1 ;; esac
g++ -DEXPECT_COMPILED=$expect_compiled -o "$tmp/consumer-pc" "$here/consumer/main.cpp" $flags
"$tmp/consumer-pc"

echo "== the installed tool finds its examples"
(cd "$tmp" && "$prefix/bin/nesshi" demo --isa | grep -q "dot3.s")
echo "== bash completion from the installed script"
got=$(bash -c 'source "$1"; COMP_WORDS=(nesshi ren); COMP_CWORD=1; _nesshi; echo "${COMPREPLY[*]}"
               COMP_WORDS=(nesshi render --ic-machine ic-r); COMP_CWORD=3; _nesshi; echo "${COMPREPLY[*]}"' _ \
      "$prefix/share/bash-completion/completions/nesshi")
[ "$got" = $'render\nic-real' ] || { echo "bash completion gave: $got"; exit 1; }
if command -v zsh >/dev/null; then zsh -n "$prefix/share/zsh/site-functions/_nesshi"; fi
if [ -n "${2:-}" ]; then
  echo "== import nesshi from the prefix"
  site=$(dirname "$(find "$prefix" -name 'nesshi.cpython-*.so')")
  (cd "$tmp" && PYTHONPATH="$site" "$2" -c 'import nesshi; print(nesshi.__file__); assert nesshi.machine("ic").name == "ic"') \
    | grep -q "^$prefix/"
  test -s "$site/nesshi.pyi" # the type stub beside it
fi
echo "installed and used: ok"
