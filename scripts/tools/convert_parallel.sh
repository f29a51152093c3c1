#!/usr/bin/env bash
# convert_parallel.sh — convert a folder of models into Billboard Clouds with
# bbcgen, one bbcgen run per model, run by GNU parallel on this machine or on
# several (see docs/batch.md).
#
#   scripts/tools/convert_parallel.sh IN OUT [-- BBCGEN ARGS...]
#
# Environment:
#   JOBS        jobs at a time per machine (default 100% = one per core)
#   BBCGEN      the tool (default: ../build/bin/bbcgen beside this script,
#               else bbcgen on PATH)
#   EXT         output format: glb (default), gltf, obj, wrl
#   REPORT      1 (default): also OUT/<name>.json (bbcgen --report); 0: not
#   MODEL_EXTS  model extensions, any case (default: obj 3ds glb gltf fbx dae
#               ply off)
#   SSHLOGIN    run on other machines too, as parallel's --sshlogin, e.g.
#               SSHLOGIN=4/host1,4/host2,: ("N/" jobs there, ":" this
#               machine). Files are not copied: IN and OUT must be on a
#               filesystem every machine sees at the same path, and BBCGEN
#               at the same path there (or BBCGEN=bbcgen on each PATH);
#               passwordless ssh. Paths are made absolute for that.
#   OMP_NUM_THREADS  threads per bbcgen (default: cores/JOBS here, at least
#               1; 1 on other machines); --threads K in the arguments wins
#
# Same outputs and rules as scripts/tools/convert.mk: every model under IN
# (subfolders too) gives OUT/<subfolder>/<name>.EXT (+ .json). A model is up
# to date, and skipped, when its output exists and neither the model nor the
# .mtl beside it with the same name is newer. Any file name is fine
# (spaces, quotes; not newlines). Models start largest file first.
#
# At the first failure no more jobs start, running ones finish (parallel
# --halt soon,fail=1), the failed model's output and report are removed, and
# the script exits with bbcgen's exit status (1..7, see docs/cli.md) after the lines
#     convert: FAILED models/x.obj (bbcgen exit 4)         (from the job)
#     convert_parallel: FAILED models/x.obj (exit 4)       (the summary)
# Exit status 1 also for a bad command line or a missing tool, 2 when IN is
# not a folder. Never reads stdin; parallel's citation notice is off
# (--will-cite).
set -euo pipefail

me=convert_parallel
usage() {
  echo "usage: $0 IN OUT [-- BBCGEN ARGS...]   (env: JOBS BBCGEN EXT REPORT MODEL_EXTS SSHLOGIN)" >&2
  exit 1
}
die() { echo "$me: $2" >&2; exit "$1"; }

[ $# -ge 2 ] || usage
in=$1 out=$2
shift 2
if [ $# -gt 0 ]; then
  [ "$1" = -- ] || usage
  shift
fi
args=("$@")
if [ -z "$in" ] || [ -z "$out" ]; then usage; fi
while [ "$in" != / ] && [ "${in%/}" != "$in" ]; do in=${in%/}; done
while [ "$out" != / ] && [ "${out%/}" != "$out" ]; do out=${out%/}; done

ext=${EXT:-glb}
report=${REPORT:-1}
model_exts=${MODEL_EXTS:-obj 3ds glb gltf fbx dae ply off}
jobs=${JOBS:-100%}
sshlogin=${SSHLOGIN:-}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [ -n "${BBCGEN:-}" ]; then
  bbcgen=$BBCGEN
elif [ -x "$here/../../build/bin/bbcgen" ]; then
  bbcgen=$(cd "$here/../../build/bin" && pwd)/bbcgen
else
  bbcgen=bbcgen
fi

command -v parallel >/dev/null 2>&1 ||
  die 1 "GNU parallel not found (Debian: apt-get install parallel)"
command -v "$bbcgen" >/dev/null 2>&1 ||
  die 1 "bbcgen not found: $bbcgen (build it, put it on PATH or set BBCGEN)"
[ -d "$in" ] || die 2 "$in: not a folder"
mkdir -p -- "$out" || die 5 "$out: cannot create the folder"

if [ -n "$sshlogin" ]; then
  # Other machines see the same absolute paths (shared filesystem).
  in=$(cd -- "$in" && pwd)
  out=$(cd -- "$out" && pwd)
  case $bbcgen in */*) bbcgen=$(cd -- "$(dirname -- "$bbcgen")" && pwd)/$(basename -- "$bbcgen") ;; esac
fi
in_abs=$(cd -- "$in" && pwd -P)
out_abs=$(cd -- "$out" && pwd -P)

tmp=$(mktemp -d "${TMPDIR:-/tmp}/$me.XXXXXX")
trap 'rm -rf -- "$tmp"' EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# The models, largest file first (the longest conversions start first rather
# than one big model running alone at the end), their outputs; skip the
# up-to-date ones.
names=()
for e in $model_exts; do names+=(-iname "*.$e" -o); done
find -L "$in" -type f \( "${names[@]}" -false \) -printf '%s\t%p\0' >"$tmp/found" ||
  die 2 "$in: could not list the models"
declare -A owner=()
todo_models=()
total=0 fresh=0
while IFS= read -r -d '' m; do
  m=${m#*$'\t'} # size TAB path
  if [ "$in" = . ]; then rel=${m#./}; else rel=${m#"$in"/}; fi
  case $in_abs/$rel/ in "$out_abs"/*) continue ;; esac # our own outputs
  o=$out/${rel%.*}.$ext
  if [ -n "${owner[$o]:-}" ]; then
    die 1 "two models would write $o: ${owner[$o]} and $m (rename one)"
  fi
  owner[$o]=$m
  total=$((total + 1))
  stale=0
  if [ ! -e "$o" ] || [ "$m" -nt "$o" ]; then stale=1; fi
  for mtl in "${m%.*}.mtl" "${m%.*}.MTL"; do
    if [ -e "$mtl" ] && [ "$mtl" -nt "$o" ]; then stale=1; fi
  done
  if [ $stale = 0 ]; then
    fresh=$((fresh + 1))
    continue
  fi
  todo_models+=("$m")
  printf '%s\0' "$m" >>"$tmp/models"
  printf '%s\0' "$o" >>"$tmp/outputs"
  mkdir -p -- "$(dirname -- "$o")"
done < <(LC_ALL=C sort -z -t $'\t' -k1,1nr -k2 "$tmp/found")

todo=${#todo_models[@]}
if [ "$todo" = 0 ]; then
  echo "$me: nothing to do: $total model(s) in $in, all up to date in $out"
  exit 0
fi
echo "$me: $total model(s) in $in, $fresh up to date, converting $todo (jobs: $jobs${sshlogin:+, sshlogin: $sshlogin})"

# Threads per bbcgen: cores/jobs here (at least 1), so that the jobs' OpenMP
# teams do not fight over the cores; 1 on other machines (JOBS defaults to
# one job per core there). OMP_NUM_THREADS set by the caller, or --threads
# in the bbcgen arguments, wins.
if [ -z "${OMP_NUM_THREADS:-}" ]; then
  ncpu=$(nproc 2>/dev/null || echo 1)
  case $jobs in
    *%) n=$((ncpu * ${jobs%\%} / 100)) ;;
    +[0-9]*) n=$((ncpu + ${jobs#+})) ;;
    -[0-9]*) n=$((ncpu - ${jobs#-})) ;;
    0) n=$ncpu ;; # no limit
    [0-9]*) n=$jobs ;;
    *) n=$ncpu ;;
  esac
  [ "$n" -gt 0 ] 2>/dev/null || n=1
  t=$((ncpu / n))
  [ "$t" -gt 0 ] || t=1
  export OMP_NUM_THREADS=$t
fi

# The job, in POSIX sh (it may run in another machine's shell); parallel
# quotes {1} (model) and {2} (output) itself.
q_bbcgen=$(printf '%q' "$bbcgen")
q_args=""
if [ ${#args[@]} -gt 0 ]; then q_args=$(printf ' %q' "${args[@]}"); fi
report_opt=""
case $report in 0 | no) ;; *) report_opt="--report {2.}.json" ;; esac
job="printf 'convert: %s\\n' {1}; rc=0; OMP_NUM_THREADS=\${OMP_NUM_THREADS:-1} $q_bbcgen {1} -o {2} $report_opt -q$q_args || rc=\$?;"
job+=" if [ \$rc -ne 0 ]; then rm -f {2} {2.}.json;"
job+=" printf 'convert: FAILED %s (bbcgen exit %s)\\n' {1} \$rc >&2; fi; exit \$rc"

# parallel's remote worker runs the job with $SHELL (sshd sets it; a bare
# environment may not): a POSIX shell is all the job needs.
export SHELL=${SHELL:-/bin/sh}
popts=(--will-cite --null --jobs "$jobs" --halt "soon,fail=1" --joblog "$tmp/joblog")
if [ -n "$sshlogin" ]; then popts+=(--sshlogin "$sshlogin"); fi
rc=0
parallel "${popts[@]}" "$job" :::: "$tmp/models" ::::+ "$tmp/outputs" </dev/null || rc=$?

if [ $rc -eq 0 ]; then
  # A job that "succeeded" without writing its output (e.g. a remote
  # worker that could not start a shell) is a failure too.
  missing=0
  i=0
  while IFS= read -r -d '' o; do
    m=${todo_models[$i]}
    i=$((i + 1))
    if [ ! -s "$o" ] || [ "$m" -nt "$o" ]; then
      echo "$me: FAILED $m: no output $o although its job reported success" >&2
      missing=$((missing + 1))
    fi
  done <"$tmp/outputs"
  if [ $missing -gt 0 ]; then exit 1; fi
  echo "$me: converted $todo model(s) into $out"
  exit 0
fi
# Name the failed model(s) from the job log (Seq = the model's line, 1-based).
failed=0
while IFS=$'\t' read -r seq _ _ _ _ _ exitval signal _; do
  [ "$seq" = Seq ] && continue
  if [ "$exitval" != 0 ] || [ "$signal" != 0 ]; then
    why="exit $exitval"
    [ "$signal" != 0 ] && why="killed by signal $signal"
    echo "$me: FAILED ${todo_models[$((seq - 1))]} ($why)" >&2
    failed=$((failed + 1))
  fi
done <"$tmp/joblog"
[ $failed -gt 0 ] || echo "$me: FAILED: parallel exit $rc" >&2
echo "$me: stopped at the first failure; models not yet converted are converted by the next run" >&2
exit "$rc"
