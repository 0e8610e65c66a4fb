#!/usr/bin/env bash
# Runs one regression case of the `anima` command line tool and checks what
# it did. Every run is limited to 1 GB of address space (ulimit -v) and 10 s
# (timeout): no input file under 1 MB may make a subcommand use more.
#
#   run_case.sh ANIMA WORKDIR [checks...] -- ARGS...
#
# WORKDIR is emptied first; the command runs inside it. Checks:
#   --exit N          the exit status must be N (default 0)
#   --stderr TEXT     stderr must contain TEXT (repeatable; also --stdout)
#   --no-stderr TEXT  stderr must not contain TEXT (also --no-stdout)
#   --quiet-stderr    stderr must be empty
#   --keep FILE       FILE is created before the run and must be unchanged after
#   --absent FILE     FILE must not exist after the run
#   --setup CMD       a bash command run in WORKDIR before the run ($ANIMA
#                     and $JSON_CHECK as for --check)
#   --check CMD       a bash command run in WORKDIR after the run; must succeed
#                     ($ANIMA and $JSON_CHECK name the two programs there)
#   --fsize KB        also limit the size of written files (ulimit -f)
#   --no-vm-limit     no address space limit (sanitizer builds reserve terabytes)
#   --timeout S       the time limit in seconds (default 10; sanitizer builds
#                     run unoptimised code several times slower)
#   --json ASSERTION  stdout must be one JSON value for which ASSERTION holds
#                     (repeatable; see json_check.cpp for the assertions)
#   --json-tool PATH  the json_check program
# After every run, stderr must be printable text (no control bytes) and no
# temporary file of the atomic writer may be left behind.
set -u

anima=$1 work=$2
shift 2
expect_exit=0 vm_limit=1 fsize="" time_limit=10
stderr_has=() stderr_lacks=() stdout_has=() stdout_lacks=() keep=() absent=() setup=() checks=() quiet=0
json=() json_tool=""
while [[ $# -gt 0 && $1 != "--" ]]; do
  case $1 in
    --exit) expect_exit=$2; shift 2 ;;
    --stderr) stderr_has+=("$2"); shift 2 ;;
    --no-stderr) stderr_lacks+=("$2"); shift 2 ;;
    --stdout) stdout_has+=("$2"); shift 2 ;;
    --no-stdout) stdout_lacks+=("$2"); shift 2 ;;
    --quiet-stderr) quiet=1; shift ;;
    --keep) keep+=("$2"); shift 2 ;;
    --absent) absent+=("$2"); shift 2 ;;
    --setup) setup+=("$2"); shift 2 ;;
    --check) checks+=("$2"); shift 2 ;;
    --fsize) fsize=$2; shift 2 ;;
    --no-vm-limit) vm_limit=0; shift ;;
    --timeout) time_limit=$2; shift 2 ;;
    --json) json+=("$2"); shift 2 ;;
    --json-tool) json_tool=$2; shift 2 ;;
    *) echo "run_case.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
shift  # --

rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 2
export ANIMA=$anima JSON_CHECK=$json_tool
for s in "${setup[@]+"${setup[@]}"}"; do
  bash -c "$s" || { echo "FAIL: setup failed: $s" >&2; exit 1; }
done
for f in "${keep[@]+"${keep[@]}"}"; do
  [[ -e $f ]] || printf 'kept content of %s\n' "$f" >"$f"
  cp -p "$f" "$f.expected"
done

(
  [[ $vm_limit == 1 ]] && ulimit -v 1048576
  [[ -n $fsize ]] && ulimit -f "$fsize"
  trap '' XFSZ
  exec timeout "$time_limit" "$anima" "$@"
) >stdout.txt 2>stderr.txt
status=$?

fail=0
report() { echo "FAIL: $*" >&2; fail=1; }
echo "anima $*"
echo "exit $status"
echo "--- stderr"; cat stderr.txt
echo "--- stdout (first 20 lines)"; head -n 20 stdout.txt

[[ $status == 124 ]] && report "timed out after $time_limit s"
[[ $status == "$expect_exit" ]] || report "exit status $status, expected $expect_exit"
for t in "${stderr_has[@]+"${stderr_has[@]}"}"; do grep -qF -- "$t" stderr.txt || report "stderr lacks: $t"; done
for t in "${stderr_lacks[@]+"${stderr_lacks[@]}"}"; do grep -qF -- "$t" stderr.txt && report "stderr has: $t"; done
for t in "${stdout_has[@]+"${stdout_has[@]}"}"; do grep -qF -- "$t" stdout.txt || report "stdout lacks: $t"; done
for t in "${stdout_lacks[@]+"${stdout_lacks[@]}"}"; do grep -qF -- "$t" stdout.txt && report "stdout has: $t"; done
[[ $quiet == 1 && -s stderr.txt ]] && report "stderr is not empty"
LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f\x7f]' stderr.txt && report "stderr has control bytes"
[[ $(tr -dc '\000' <stderr.txt | wc -c) -gt 0 ]] && report "stderr has NUL bytes"
for f in "${keep[@]+"${keep[@]}"}"; do cmp -s "$f" "$f.expected" || report "$f was changed"; done
for f in "${absent[@]+"${absent[@]}"}"; do [[ -e $f ]] && report "$f was written"; done
leftover=$(find . -name '.*.tmp' | head -n 1)
[[ -n $leftover ]] && report "temporary file left behind: $leftover"
for c in "${checks[@]+"${checks[@]}"}"; do bash -c "$c" || report "check failed: $c"; done
if [[ ${#json[@]} -gt 0 ]]; then
  if [[ -z $json_tool ]]; then report "--json needs --json-tool"
  else "$json_tool" stdout.txt "${json[@]}" || report "JSON assertions failed"; fi
fi
exit $fail
