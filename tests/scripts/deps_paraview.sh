#!/usr/bin/env bash
# scripts/deps.sh beside ParaView: with python3-paraview installed and libvtk9-dev not, it stops
# before apt with one message saying what to do; with neither conflict nor anything missing it
# touches nothing. dpkg-query and apt-get are stubs on PATH (the stub apt-get fails the test if
# it is called), so the machine's packages are never read or changed.
#   deps_paraview.sh <repo root> <work folder>
set -euo pipefail
root=$1 work=$2
rm -rf "$work" && mkdir -p "$work/bin"

# Packages installed in the stub's world: one name per line in $work/installed.
cat > "$work/bin/dpkg-query" <<'STUB'
#!/usr/bin/env bash
package=${!#}
if grep -qx "$package" "$KDEM_TEST_INSTALLED"; then printf 'ii '; else exit 1; fi
STUB
cat > "$work/bin/apt-get" <<'STUB'
#!/usr/bin/env bash
echo "apt-get called: $*" >&2
exit 99
STUB
chmod +x "$work/bin/dpkg-query" "$work/bin/apt-get"
export KDEM_TEST_INSTALLED=$work/installed
run_deps() { PATH="$work/bin:$PATH" "$root/scripts/deps.sh" --no-kokkos > "$work/out" 2>&1; }
fail() { echo "FAIL: $*"; cat "$work/out"; exit 1; }

all_packages=$(sed -n '/^APT_PACKAGES=(/,/)/p' "$root/scripts/deps.sh" | tr -d '()' |
  sed 's/APT_PACKAGES=//' | tr ' ' '\n' | sed '/^$/d')

# 1. ParaView with its Python module, no VTK development files: refused, apt never called.
{ echo paraview; echo python3-paraview; } > "$work/installed"
if run_deps; then fail "deps.sh went on beside python3-paraview"; fi
grep -q "python3-paraview" "$work/out" || fail "the message does not name python3-paraview"
grep -q "apt-get remove python3-paraview" "$work/out" || fail "the message does not say what to do"
if grep -q "apt-get called" "$work/out"; then fail "apt-get ran before the refusal"; fi

# 2. Everything installed (ParaView without its Python module): nothing to do, apt not called.
{ echo "$all_packages"; echo paraview; } > "$work/installed"
run_deps || fail "deps.sh failed with every package installed"

# 3. python3-paraview installed but VTK too (cannot happen through apt; no refusal then).
{ echo "$all_packages"; echo python3-paraview; } > "$work/installed"
run_deps || fail "deps.sh refused although libvtk9-dev is installed"
echo "deps.sh beside ParaView: refused with the fix named, quiet when nothing is missing"
