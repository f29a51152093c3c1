#!/usr/bin/env bash
# test_convert.sh BBCGEN — batch conversion of a folder (docs/batch.md):
# scripts/tools/convert.mk (make -j2), scripts/tools/convert_parallel.sh (GNU parallel,
# skipped when it is not installed; also its SSHLOGIN path through a fake
# ssh that runs here) and scripts/tools/convert_slurm.sbatch (run by hand, one
# array task at a time) on three small generated trees: valid outputs, a
# second run converts nothing, a touched model or .mtl is the only one
# redone, a damaged model stops the run naming it and leaves no output.
# bbcgen runs are counted through a wrapper that logs each model.
# Last line: "N passed, M failed"; exit status 1 when M > 0.
# Conditions are single-quoted strings that check() evals (SC2016), reading
# variables set just before (SC2034); mk and par take optional arguments.
# shellcheck disable=SC2016,SC2034,SC2119,SC2120
set -euo pipefail

if [ $# -ne 1 ]; then
  echo "usage: $0 BBCGEN_PATH" >&2
  exit 2
fi
if [ ! -f "$1" ] || [ ! -x "$1" ]; then
  echo "test_convert: $1: not an executable" >&2
  exit 2
fi
real=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
scripts=$(cd "$(dirname "${BASH_SOURCE[0]}")/../scripts" && pwd)
export LC_ALL=C
# A make above us (make test -> ctest -> here) must not pass -k, -i, -n or
# its jobserver to ours.
unset MAKEFLAGS MFLAGS MAKELEVEL MAKEOVERRIDES
unset JOBS SSHLOGIN EXT REPORT MODEL_EXTS PER_TASK SLURM_ARRAY_TASK_ID BBCGEN

tmp=$(mktemp -d "${TMPDIR:-/tmp}/test_convert.XXXXXX")
tmp=$(cd "$tmp" && pwd)
trap 'rm -rf -- "$tmp"' EXIT

passed=0 failed=0
pass() { passed=$((passed + 1)); echo "ok   $1"; }
fail() { failed=$((failed + 1)); echo "FAIL $1"; }
out=""
# check DESCRIPTION 'SHELL CONDITION': on failure, the last command's output
# ($out) is shown under the line.
check() {
  if eval "$2"; then
    pass "$1"
  else
    fail "$1"
    if [ -n "$out" ]; then printf '%s\n' "$out" | sed 's/^/     | /'; fi
  fi
}

# bbcgen, logging each model it is run on.
log=$tmp/bbcgen.log
: >"$log"
wrapper=$tmp/bbcgen
{
  echo '#!/bin/bash' # %q quotes as bash reads (a path with non-ASCII letters: $'...')
  printf 'printf "%%s\\n" "$1" >>%q\n' "$log"
  printf 'exec %q "$@"\n' "$real"
} >"$wrapper"
chmod +x "$wrapper"
export BBCGEN=$wrapper
runs() { grep -c '' "$log" || true; }
# The models bbcgen ran on since log line $1, sorted, one line.
ran_since() { tail -n "+$(($1 + 1))" "$log" | LC_ALL=C sort | tr '\n' ' ' | sed 's/ $//'; }

# A .glb: non-empty, "glTF", version 2, header length = file size.
valid_glb() {
  [ -s "$1" ] && [ "$(head -c 4 "$1")" = glTF ] || return 1
  local v n
  v=$(od -An -tu4 -j4 -N4 "$1" | tr -d ' ')
  n=$(od -An -tu4 -j8 -N4 "$1" | tr -d ' ')
  [ "$v" = 2 ] && [ "$n" = "$(stat -c %s "$1")" ]
}
all_valid() { # all_valid OUTDIR: the three clouds and their reports
  local o
  for o in oak pine sub/birch; do
    valid_glb "$1/$o.glb" && [ -s "$1/$o.json" ] || return 1
  done
}
snapshot() { (cd "$1" && find . -type f -printf '%p %T@\n' | LC_ALL=C sort); }
mtime() { stat -c %y "$1"; }
no_leftovers() { [ -z "$(find "$1" -name '*.tmp.*' -print -quit)" ]; }
# touch a model (or .mtl) so that it is newer than every output.
bump() {
  touch "$1"
  if [ -n "$(find "$2" -type f -newer "$1" -print -quit)" ]; then
    sleep 1
    touch "$1"
  fi
}

# Three small trees, one in a subfolder.
m=$tmp/models
mkdir -p "$m/sub"
"$real" tree --species oak --seed 1 --leaves 300 -q -o "$m/oak.obj"
"$real" tree --species pine --seed 2 --leaves 300 -q -o "$m/pine.obj"
"$real" tree --species birch --seed 3 --leaves 300 -q -o "$m/sub/birch.obj"
# Damaged: a face with a vertex index out of range (bbcgen exit 4).
bad=$tmp/bad.obj
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' >"$bad"


# ---------------------------------------------------------------- make
echo "== make -f scripts/tools/convert.mk -j2"
o=$tmp/out_make
mk() { make -f "$scripts/tools/convert.mk" IN="$m/" OUT="$o" BBCGEN="$wrapper" -j2 "$@" 2>&1; }
three="$m/oak.obj $m/pine.obj $m/sub/birch.obj"
n0=$(runs)
rc=0; out=$(mk) || rc=$?
check "make: first run succeeds" '[ $rc = 0 ]'
check "make: 3 valid clouds (glTF) and reports" 'all_valid "$o"'
check "make: bbcgen ran once per model" '[ "$(ran_since "$n0")" = "$three" ]'

snap=$(snapshot "$o")
n0=$(runs)
rc=0; out=$(mk) || rc=$?
check "make: second run succeeds and says nothing to do" \
  '[ $rc = 0 ] && grep -q "Nothing to be done for .all." <<<"$out"'
check "make: second run runs no bbcgen, outputs as they were" \
  '[ "$(runs)" = "$n0" ] && [ "$(snapshot "$o")" = "$snap" ]'

bump "$m/pine.obj" "$o"
t_oak=$(mtime "$o/oak.glb") t_birch=$(mtime "$o/sub/birch.glb") t_pine=$(mtime "$o/pine.glb")
n0=$(runs)
rc=0; out=$(mk) || rc=$?
check "make: touched model: only it is converted" \
  '[ $rc = 0 ] && [ "$(ran_since "$n0")" = "$m/pine.obj" ]'
check "make: touched model: its output is new, the others untouched" \
  '[ "$(mtime "$o/pine.glb")" != "$t_pine" ] && [ "$(mtime "$o/oak.glb")" = "$t_oak" ] &&
   [ "$(mtime "$o/sub/birch.glb")" = "$t_birch" ] && valid_glb "$o/pine.glb"'

bump "$m/sub/birch.mtl" "$o"
n0=$(runs)
rc=0; out=$(mk) || rc=$?
check "make: touched .mtl: only its model is converted" \
  '[ $rc = 0 ] && [ "$(ran_since "$n0")" = "$m/sub/birch.obj" ]'

cp "$bad" "$m/bad.obj"
snap=$(snapshot "$o")
rc=0; out=$(mk) || rc=$?
check "make: damaged model: make fails" '[ $rc != 0 ]'
check "make: damaged model: the failure names it" \
  'grep -qF "convert: FAILED $m/bad.obj (bbcgen exit 4)" <<<"$out"'
check "make: damaged model: no output, no report, no temporary file" \
  '[ ! -e "$o/bad.glb" ] && [ ! -e "$o/bad.json" ] && no_leftovers "$o"'
check "make: damaged model: the other outputs untouched" '[ "$(snapshot "$o")" = "$snap" ]'
rm "$m/bad.obj"

cp "$m/oak.obj" "$m/two words.obj"
n0=$(runs)
rc=0; out=$(mk) || rc=$?
check "make: a name with a space stops make, naming it, converting nothing" \
  '[ $rc != 0 ] && grep -qF "$m/two words.obj" <<<"$out" && [ "$(runs)" = "$n0" ]'
rm "$m/two words.obj"

# ------------------------------------------------------------ parallel
if command -v parallel >/dev/null 2>&1; then
  echo "== scripts/tools/convert_parallel.sh (JOBS=2)"
  o=$tmp/out_parallel
  par() { JOBS=2 "$scripts/tools/convert_parallel.sh" "$m" "$o" "$@" </dev/null 2>&1; }
  n0=$(runs)
  rc=0; out=$(par) || rc=$?
  check "parallel: first run succeeds" '[ $rc = 0 ]'
  check "parallel: 3 valid clouds (glTF) and reports" 'all_valid "$o"'
  check "parallel: bbcgen ran once per model" '[ "$(ran_since "$n0")" = "$three" ]'
  check "parallel: the same clouds as make" 'cmp -s "$o/oak.glb" "$tmp/out_make/oak.glb"'

  snap=$(snapshot "$o")
  n0=$(runs)
  rc=0; out=$(par) || rc=$?
  check "parallel: second run succeeds and says nothing to do" \
    '[ $rc = 0 ] && grep -q "nothing to do" <<<"$out"'
  check "parallel: second run runs no bbcgen, outputs as they were" \
    '[ "$(runs)" = "$n0" ] && [ "$(snapshot "$o")" = "$snap" ]'

  bump "$m/oak.obj" "$o"
  t_pine=$(mtime "$o/pine.glb")
  n0=$(runs)
  rc=0; out=$(par) || rc=$?
  check "parallel: touched model: only it is converted, the others untouched" \
    '[ $rc = 0 ] && [ "$(ran_since "$n0")" = "$m/oak.obj" ] && [ "$(mtime "$o/pine.glb")" = "$t_pine" ]'

  # SSHLOGIN: parallel's remote path (ssh, its perl wrapper, quoting) through
  # a fake ssh that runs the command here (a shared filesystem, as documented).
  fakessh=$tmp/fakessh
  {
    echo '#!/bin/sh'
    printf 'echo "$*" >>%q\n' "$tmp/ssh.log"
    echo 'while [ $# -gt 0 ]; do'
    echo '  case $1 in -l | -p | -o) shift 2 ;; -*) shift ;; *) shift; [ "${1:-}" = -- ] && shift; break ;; esac'
    echo 'done'
    echo 'SHELL=${SHELL:-/bin/sh} exec sh -c "$*"' # sshd gives the login shell
  } >"$fakessh"
  chmod +x "$fakessh"
  bump "$m/sub/birch.obj" "$o"
  n0=$(runs)
  rc=0; out=$(SSHLOGIN=1/farhost PARALLEL_SSH=$fakessh par) || rc=$?
  out+=$'\n'"ssh calls: $(cat "$tmp/ssh.log" 2>/dev/null)"$'\n'"bbcgen ran on: $(ran_since "$n0")"
  check "parallel: SSHLOGIN: the job runs through ssh on the host, valid output" \
    '[ $rc = 0 ] && grep -q "^farhost " "$tmp/ssh.log" && [ "$(ran_since "$n0")" = "$m/sub/birch.obj" ] &&
     valid_glb "$o/sub/birch.glb"'

  # A remote that "succeeds" without running the job: no output, a failure.
  noop=$tmp/noopssh
  printf '#!/bin/sh\nexit 0\n' >"$noop"
  chmod +x "$noop"
  bump "$m/sub/birch.obj" "$o"
  rc=0; out=$(SSHLOGIN=1/farhost PARALLEL_SSH=$noop par) || rc=$?
  check "parallel: a job that succeeds without output is a failure, named" \
    '[ $rc = 1 ] && grep -qF "no output $o/sub/birch.glb" <<<"$out"'
  rc=0; out=$(par) || rc=$?

  odd="it's two words"
  cp "$m/oak.obj" "$m/$odd.obj"
  rc=0; out=$(par) || rc=$?
  check "parallel: any file name (a quote, spaces)" '[ $rc = 0 ] && valid_glb "$o/$odd.glb"'
  rm -f "$m/$odd.obj" "$o/$odd.glb" "$o/$odd.json"

  cp "$bad" "$m/bad.obj"
  snap=$(snapshot "$o")
  rc=0; out=$(par) || rc=$?
  check "parallel: damaged model: exits with bbcgen's status 4" '[ $rc = 4 ]'
  check "parallel: damaged model: the failure names it" \
    'grep -qF "convert_parallel: FAILED $m/bad.obj (exit 4)" <<<"$out" &&
     grep -qF "convert: FAILED $m/bad.obj (bbcgen exit 4)" <<<"$out"'
  check "parallel: damaged model: no output, no report, no temporary file" \
    '[ ! -e "$o/bad.glb" ] && [ ! -e "$o/bad.json" ] && no_leftovers "$o"'
  check "parallel: damaged model: the other outputs untouched" '[ "$(snapshot "$o")" = "$snap" ]'
  rm "$m/bad.obj"
else
  echo "== SKIPPED: the scripts/tools/convert_parallel.sh checks: GNU parallel is not installed (apt-get install parallel)"
fi

# --------------------------------------------------------------- slurm
echo "== scripts/tools/convert_slurm.sbatch, run by hand for each array task"
o=$tmp/out_slurm
list() { (cd "$tmp" && find models -type f -iname '*.obj' | LC_ALL=C sort >models.txt); }
task() { (cd "$tmp" && SLURM_ARRAY_TASK_ID=$1 bash "$scripts/tools/convert_slurm.sbatch" models.txt models "$o" 2>&1); }
list
n0=$(runs)
ok=1 all=""
for t in 0 1 2; do
  rc=0; out=$(task $t) || rc=$?
  all+=$out$'\n'
  [ $rc = 0 ] || ok=0
done
out=$all
check "slurm: tasks 0..2 succeed" '[ $ok = 1 ]'
check "slurm: 3 valid clouds (glTF) and reports" 'all_valid "$o"'
check "slurm: bbcgen ran once per model" \
  '[ "$(ran_since "$n0")" = "models/oak.obj models/pine.obj models/sub/birch.obj" ]'
rc=0; out=$(task 3) || rc=$?
check "slurm: a task past the list's end does nothing, exit 0" \
  '[ $rc = 0 ] && grep -q "nothing to do" <<<"$out"'

snap=$(snapshot "$o")
n0=$(runs)
ok=1 all=""
for t in 0 1 2; do
  rc=0; out=$(task $t) || rc=$?
  all+=$out$'\n'
  if [ $rc != 0 ] || ! grep -q "up to date" <<<"$out"; then ok=0; fi
done
out=$all
check "slurm: rerun: every task up to date, no bbcgen run, outputs as they were" \
  '[ $ok = 1 ] && [ "$(runs)" = "$n0" ] && [ "$(snapshot "$o")" = "$snap" ]'

cp "$bad" "$m/bad.obj"
list
bad_task=$(($(grep -n '^models/bad\.obj$' "$tmp/models.txt" | cut -d: -f1) - 1))
n0=$(runs)
ok=1 all=""
for t in 0 1 2 3; do
  rc=0; out=$(task $t) || rc=$?
  all+=$out$'\n'
  if [ $t = $bad_task ]; then
    check "slurm: damaged model: its task exits with bbcgen's status 4, naming it" \
      '[ $rc = 4 ] && grep -qF "convert: FAILED models/bad.obj (bbcgen exit 4)" <<<"$out"'
  elif [ $rc != 0 ]; then
    ok=0
  fi
done
out=$all
check "slurm: damaged model: the other tasks succeed, only it was run" \
  '[ $ok = 1 ] && [ "$(ran_since "$n0")" = "models/bad.obj" ]'
check "slurm: damaged model: no output, no report, no temporary file" \
  '[ ! -e "$o/bad.glb" ] && [ ! -e "$o/bad.json" ] && no_leftovers "$o"'
rm "$m/bad.obj"

rc=0; out=$(cd "$tmp" && bash "$scripts/tools/convert_slurm.sbatch" models.txt models "$o" 2>&1) || rc=$?
check "slurm: without SLURM_ARRAY_TASK_ID: exit 1 with a message" \
  '[ $rc = 1 ] && grep -q SLURM_ARRAY_TASK_ID <<<"$out"'

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
