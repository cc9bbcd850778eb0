#!/bin/sh
# Installs marsyn from the build tree into a scratch prefix, builds the out-of-tree example
# plugin against the installed CMake package, and checks that the installed marsyn loads it.
set -eu
build="$1"; src="$2"; scratch="$3"
rm -rf "$scratch"; mkdir -p "$scratch"
cmake --install "$build" --prefix "$scratch/prefix" > "$scratch/install.log"
# The ABI and the numerics it is written in install side by side, as two exported targets.
for h in plugin.hpp tracker.hpp fast_interval.hpp dual.hpp interval.hpp binary_file.hpp; do
  [ -f "$scratch/prefix/include/marsyn/$h" ] || { echo "installed headers lack marsyn/$h"; exit 1; }
done
grep -q "marsyn::numerics" "$scratch/prefix"/lib*/cmake/marsyn/marsynTargets.cmake ||
  { echo "the installed package does not export marsyn::numerics"; exit 1; }
cmake -S "$src/examples/out_of_tree_plugin" -B "$scratch/plugin" -DCMAKE_PREFIX_PATH="$scratch/prefix" \
      -DCMAKE_BUILD_TYPE=Release > "$scratch/configure.log"
cmake --build "$scratch/plugin" -j 2 > "$scratch/build.log"
MARSYN_PLUGIN_PATH="$scratch/plugin" "$scratch/prefix/bin/marsyn" plugins > "$scratch/plugins.txt"
grep -q "kinematic_car" "$scratch/plugins.txt" || { echo "kinematic_car not listed:"; cat "$scratch/plugins.txt"; exit 1; }
# The installed marsyn must find its own plugins without any environment (install layout).
"$scratch/prefix/bin/marsyn" plugins | grep -q "unicycle" || { echo "installed marsyn lost its plugins"; exit 1; }
# A problem using the third-party model validates with the installed marsyn.
sed "s|plugin_paths: \[build\]|plugin_paths: [$scratch/plugin]|" "$src/examples/out_of_tree_plugin/kinematic_car.yaml" \
    > "$scratch/kinematic_car.yaml"
"$scratch/prefix/bin/marsyn" check "$scratch/kinematic_car.yaml"
echo "out-of-tree plugin: built against the installed package and loaded"
