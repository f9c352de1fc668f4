#!/usr/bin/env bash
# Packs built programs with Debian's Open MPI runtime, for a benchmark machine that has neither
# MPI, HDF5 nor the other libraries (a lent node without package access).
#   scripts/bench/pack_runtime.sh OUTDIR PROGRAM...     e.g. build/v4/ringdem /usr/bin/lmp
# OUTDIR gets bin/ (the programs and Open MPI's launcher), lib/ (every shared library they and
# the MPI plugins load, glibc and its loader included), ompi/ and pmix/lib/pmix/ (the plugins),
# share/ (Open MPI's help texts) and mpirun.sh, a launcher that runs every process under the
# packed loader with --library-path: nothing of the machine's own libraries is used, and no
# LD_LIBRARY_PATH leaks into the machine's own tools. On the other machine:
#   OUTDIR/mpirun.sh -np 16 --bind-to core OUTDIR/bin/ringdem run case.yaml
# which scripts/bench/scaling.sh takes as MPIRUN=OUTDIR/mpirun.sh. Single node only: the ranks
# are the launcher's own children (no remote daemons). The interconnect plugins (UCX, OFI,
# verbs, PSM) are left out; ranks talk through shared memory.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 OUTDIR PROGRAM..." >&2; exit 2; }
out=$1; shift
multiarch=/usr/lib/x86_64-linux-gnu
[ -d "$multiarch/openmpi/lib/openmpi3" ] || { echo "needs Debian's Open MPI (openmpi-bin)" >&2; exit 1; }
rm -rf "$out"
mkdir -p "$out/lib" "$out/bin" "$out/ompi" "$out/pmix/lib/pmix" "$out/share"
cp -L "$multiarch"/openmpi/lib/openmpi3/*.so "$out/ompi/"
for pattern in ucx ofi openib psm verbs mtl_ spml sshmem scoll memheap atomic_ cuda; do
  rm -f "$out"/ompi/*"$pattern"*
done
cp -L "$multiarch"/pmix2/lib/pmix/*.so "$out/pmix/lib/pmix/"
cp -rL /usr/share/openmpi "$out/share/"
launcher=$(readlink -f "$(command -v orterun)")
cp -L "$launcher" "$out/bin/orterun"
for program in "$@"; do cp -L "$program" "$out/bin/"; done
for object in "$out"/bin/* "$out"/ompi/*.so "$out"/pmix/lib/pmix/*.so; do
  ldd "$object" 2>/dev/null | awk '/=> \//{print $3} /^\t\/lib64\//{print $1}'
done | sort -u | while read -r library; do cp -L "$library" "$out/lib/"; done
cat >"$out/mpirun.sh" <<'LAUNCH'
#!/usr/bin/env bash
# mpirun.sh [-np N] [--bind-to X] [--map-by X] [-flag]... PROGRAM ARGS (see pack_runtime.sh)
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
loader="$here/lib/ld-linux-x86-64.so.2"
export OPAL_PKGDATADIR="$here/share/openmpi" OPAL_PKGLIBDIR="$here/ompi"
# PMIx looks for its plugins under its install prefix: the machine may have its own PMIx
# there, of another version, whose plugins would not load into the packed one.
export OMPI_MCA_mca_base_component_path="$here/ompi" PMIX_PREFIX="$here/pmix" PMIX_LIBDIR="$here/pmix/lib"
export PMIX_PKGLIBDIR="$here/pmix/lib/pmix"
export PMIX_MCA_mca_base_component_path="$here/pmix/lib/pmix"
export OMPI_MCA_pml=ob1 OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none
export OMPI_MCA_btl_base_warn_component_unused=0
# hwloc would load the machine's own plugins (GPU, OpenCL) into the packed library: none.
export HWLOC_PLUGINS_PATH="$here/no-hwloc-plugins"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
options=()
while [ $# -gt 0 ]; do
  case "$1" in
    -np | -n | --bind-to | --map-by) options+=("$1" "$2"); shift 2 ;;
    -*) options+=("$1"); shift ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || { echo "mpirun.sh: no program given" >&2; exit 2; }
program=$1; shift
exec "$loader" --library-path "$here/lib" "$here/bin/orterun" "${options[@]}" \
  "$loader" --library-path "$here/lib" "$program" "$@"
LAUNCH
chmod +x "$out/mpirun.sh"
du -sh "$out"
