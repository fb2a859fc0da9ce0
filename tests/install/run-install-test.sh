#!/usr/bin/env bash
# The program as a user gets it, installed, not as the build folder holds it.
#   run-install-test.sh install BUILD_DIR VERSION   `cmake --install` into BUILD_DIR/install-test/staging
#   run-install-test.sh package BUILD_DIR VERSION   `cpack` writes the .deb into BUILD_DIR/package-test,
#                                                   checked with dpkg-deb -I/-c and extracted there
#                                                   (dpkg-deb -x; never installed on the machine)
# Either way the tree holds bin/meshtour and the documentation and nothing of the tests or the
# benchmarks, and the installed program, run from an empty folder outside the source and build
# trees, prints its version, describes a small mesh (`info`) and renders a two-frame tour.
set -euo pipefail
mode=${1:?usage: run-install-test.sh install|package BUILD_DIR VERSION}
build=$(cd "${2:?build folder}" && pwd)
version=${3:?project version}

fail() { echo "FAIL: $*" >&2; exit 1; }

case "$mode" in
  install)
    work="$build/install-test"
    rm -rf "$work"
    mkdir -p "$work"
    cmake --install "$build" --prefix "$work/staging" >"$work/install.log"
    root="$work/staging"
    exe="$root/bin/meshtour"
    docdir="$root/share/doc/meshtour"
    ;;
  package)
    work="$build/package-test"
    rm -rf "$work"
    mkdir -p "$work"
    (cd "$build" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work") >"$work/cpack.log" 2>&1 ||
      { cat "$work/cpack.log" >&2; fail "cpack could not make the package"; }
    debs=("$work"/meshtour_"$version"_*.deb)
    [ -f "${debs[0]}" ] || fail "cpack wrote no meshtour_${version}_*.deb into $work (see $work/cpack.log)"
    deb="${debs[0]}"

    dpkg-deb -I "$deb" >"$work/info.txt"
    field() { dpkg-deb -f "$deb" "$1"; }
    [ "$(field Package)" = meshtour ] || fail "Package is '$(field Package)', not meshtour"
    [ "$(field Version)" = "$version" ] || fail "Version is '$(field Version)', not the project's $version"
    [ -n "$(field Maintainer)" ] || fail "the package names no Maintainer"
    [ -n "$(field Description)" ] || fail "the package has no Description"
    depends=$(field Depends)
    echo "Depends: $depends"
    # dpkg-shlibdeps must have found the libraries the program links, and the font it looks up.
    for library in libembree3 libtbb libopenimageio libavcodec libavformat libavfilter libswscale \
                   libfreetype libfontconfig libqhull-r libdraco libmeshoptimizer libc6 libstdc++6 fonts-dejavu-core; do
      grep -q "\\b$library" <<<"$depends" || fail "Depends lacks $library: $depends"
    done
    # Every dependency names a Debian package that exists: each alternative group has one
    # installed here, where the program was built and runs.
    IFS=',' read -ra groups <<<"$depends"
    for group in "${groups[@]}"; do
      found=0
      IFS='|' read -ra alternatives <<<"$group"
      for alternative in "${alternatives[@]}"; do
        name=$(awk '{print $1}' <<<"$alternative")
        dpkg-query -W -f='${Status}' "$name" 2>/dev/null | grep -q 'install ok installed' && found=1
      done
      [ "$found" = 1 ] || fail "no package of the dependency '$group' is installed here"
    done

    dpkg-deb -c "$deb" | awk '{print $NF}' >"$work/contents.txt"
    grep -qx './usr/bin/meshtour' "$work/contents.txt" || fail "the package lacks ./usr/bin/meshtour"
    dpkg-deb -x "$deb" "$work/root"
    root="$work/root/usr"
    exe="$root/bin/meshtour"
    docdir="$root/share/doc/meshtour"
    ;;
  *) fail "unknown mode '$mode' (install or package)" ;;
esac

# What is installed: the program alone in bin/, its documentation, nothing of the tests or benchmarks.
[ -x "$exe" ] || fail "$exe is missing or not executable"
[ "$(ls "$(dirname "$exe")")" = meshtour ] || fail "bin/ holds more than meshtour: $(ls "$(dirname "$exe")" | tr '\n' ' ')"
for doc in README.md docs/OPTIONS.md docs/METHOD.md scenes/README.md scenes/default.json; do
  [ -s "$docdir/$doc" ] || fail "the documentation lacks $doc (under $docdir)"
done
if find "$root" -type f \( -perm -u+x -o -name '*.a' -o -name '*.so*' \) ! -path "$exe" | grep .; then
  fail "programs or libraries besides bin/meshtour were installed (listed above)"
fi

# The installed program, from an empty folder: a wrong run-time path into the source or build
# tree would show here.
run="$work/run"
mkdir -p "$run"
cd "$run"
[ "$("$exe" --version)" = "meshtour $version" ] || fail "--version printed '$("$exe" --version)', not 'meshtour $version'"

# A small mesh: an octahedron (6 vertices, 8 triangles).
cat >octahedron.obj <<'OBJ'
v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
OBJ
"$exe" info octahedron.obj --json >info.json || fail "meshtour info octahedron.obj failed"
grep -q '"triangles": *8\b' info.json || { cat info.json >&2; fail "meshtour info does not report the octahedron's 8 triangles"; }

"$exe" tour octahedron.obj --frames 2 --width 64 --height 36 -o tour.mp4 >tour.log 2>&1 ||
  { cat tour.log >&2; fail "meshtour tour octahedron.obj failed"; }
[ -s tour.mp4 ] || fail "meshtour tour wrote no tour.mp4"
echo "installed meshtour $version ($mode) under $root: --version, info and a 2-frame tour ran"
