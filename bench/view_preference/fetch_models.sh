#!/usr/bin/env bash
# Brings the models of labels.json back from their public GitHub repositories, at the commits the
# labels were made on, into a directory outside the repository (default: ./view-preference-models).
# Needs git; the four DanishStatues models also need Blender (3.x) to turn their FBX into OBJ.
# The six shared meshes are not fetched: they are ../shared/meshes/*.ply beside the repository.
# Not used by CI.
set -euo pipefail
out=${1:-view-preference-models}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# repository commit path-in-repository file-written
models=(
  "alecjacobson/common-3d-test-models 8a4f8642acaf43f9cd7b67858a1502e1055ef202 data/nefertiti.obj aj_nefertiti.obj"
  "alecjacobson/common-3d-test-models 8a4f8642acaf43f9cd7b67858a1502e1055ef202 data/igea.ply aj_igea.ply"
  "alecjacobson/common-3d-test-models 8a4f8642acaf43f9cd7b67858a1502e1055ef202 data/ogre.obj aj_ogre.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/boot/boot.obj os_boot.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/cat/cat-low-resolution.obj os_cat-low-resolution.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/demosthenes/demosthenes-low-res.obj os_demosthenes-low-res.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/falconstatue/falconstatue.obj os_falconstatue.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/goathead/goathead.obj os_goathead.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/koala/koala_low_resolution.obj os_koala_low_resolution.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/lionstatue/lionstatue.obj os_lionstatue.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/skull/skull_low_resolution.obj os_skull_low_resolution.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/penguin/penguin.obj os_penguin.obj"
  "odedstein/meshes 835213277571d625722d25880c9c3010c6f45a5a objects/cow/cow-low-resolution.obj os_cow-low-resolution.obj"
  "libigl/libigl-tutorial-data c1f9ede366d02e3531ecbaec5e3769312f31cccd decimated-max.obj li_decimated-max.obj"
  "libigl/libigl-tutorial-data c1f9ede366d02e3531ecbaec5e3769312f31cccd fertility.off li_fertility.off"
  "libigl/libigl-tutorial-data c1f9ede366d02e3531ecbaec5e3769312f31cccd lion.off li_lion.off"
  "ptrvilya/blendify b0faafd169d32eeef3cebfa3bb04400d8e6a1137 examples/assets/lucy.ply bf_lucy.ply"
  "unclejimbo/Euclid e118abdcdf51b6bc05cf5aa056bf228e052cf501 data/dragon.ply eu_dragon.ply"
  "unclejimbo/Euclid e118abdcdf51b6bc05cf5aa056bf228e052cf501 data/chair.off eu_chair.off"
  "unclejimbo/Euclid e118abdcdf51b6bc05cf5aa056bf228e052cf501 data/face.off eu_face.off"
  "keijiro/DanishStatues 571dccace2b053138fef6fd654ba58ca372b6f40 Packages/jp.keijiro.danish-statues/Runtime/BustManWreath/BustManWreath.fbx BustManWreath.fbx"
  "keijiro/DanishStatues 571dccace2b053138fef6fd654ba58ca372b6f40 Packages/jp.keijiro.danish-statues/Runtime/DancingGirl/DancingGirl.fbx DancingGirl.fbx"
  "keijiro/DanishStatues 571dccace2b053138fef6fd654ba58ca372b6f40 Packages/jp.keijiro.danish-statues/Runtime/Maria/Maria.fbx Maria.fbx"
  "keijiro/DanishStatues 571dccace2b053138fef6fd654ba58ca372b6f40 Packages/jp.keijiro.danish-statues/Runtime/Ugolino/Ugolino.fbx Ugolino.fbx"
)

for m in "${models[@]}"; do
  read -r repo commit path file <<<"$m"
  dir="$work/${repo//\//+}"
  if [ ! -d "$dir" ]; then
    git clone --quiet --filter=blob:none --no-checkout "https://github.com/$repo.git" "$dir"
  fi
  git -C "$dir" show "$commit:$path" >"$out/$file"
  echo "$out/$file  <- $repo@$commit:$path"
done

# The DanishStatues ship FBX (Unity package), which meshtour does not read: Blender's FBX importer
# and OBJ exporter (triangulated, +Y up, -Z forward, no normals/UVs/materials) make the OBJ the
# labels were made on.
if command -v blender >/dev/null; then
  cat >"$work/fbx2obj.py" <<'PY'
import bpy, sys
src, dst = sys.argv[sys.argv.index('--') + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.fbx(filepath=src)
bpy.ops.export_scene.obj(filepath=dst, use_selection=False, use_materials=False, use_uvs=False,
                         use_normals=False, use_triangles=True, axis_forward='-Z', axis_up='Y')
PY
  for n in BustManWreath DancingGirl Maria Ugolino; do
    blender -b --python "$work/fbx2obj.py" -- "$out/$n.fbx" "$out/ds_$n.obj" >/dev/null
    echo "$out/ds_$n.obj  <- $n.fbx (Blender)"
  done
else
  echo "blender not found: the four DanishStatues FBX files were fetched but not converted to OBJ" >&2
fi
