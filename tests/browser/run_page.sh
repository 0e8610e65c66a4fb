#!/usr/bin/env bash
# Opens a page `anima view` (or a --view option) wrote in headless Chromium
# and checks the state the player shows on <body>, and that it logged
# nothing to the console.
#
#   run_page.sh CHROMIUM ANIMA WORKDIR [checks...] -- ANIMA-ARGS...
#
# WORKDIR is emptied, `anima ANIMA-ARGS` runs in it and must write page.html
# (unless --page names another file). Checks:
#   --page FILE          the page to open (default page.html)
#   --equal NAME=VALUE   <body data-NAME> must be VALUE after the run (repeatable)
#   --more NAME=VALUE    <body data-NAME> must be a number above VALUE
#   --same NAME          <body data-NAME> in the browser must equal the value
#                        the CLI wrote into the file (the player counted
#                        what the CLI counted)
#   --no-webgl           start Chromium without WebGL (the canvas fallback)
#   --budget MS          virtual time the page runs for (default 2000)
# Exits 77 (CTest's SKIP_RETURN_CODE) when Chromium is not installed.
set -u

chromium=$1 anima=$2 work=$3
shift 3
page=page.html budget=2000 webgl=1
equal=() more=() same=()
while [[ $# -gt 0 && $1 != "--" ]]; do
  case $1 in
    --page) page=$2; shift 2 ;;
    --equal) equal+=("$2"); shift 2 ;;
    --more) more+=("$2"); shift 2 ;;
    --same) same+=("$2"); shift 2 ;;
    --no-webgl) webgl=0; shift ;;
    --budget) budget=$2; shift 2 ;;
    *) echo "run_page.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
shift  # --

if [[ -z $chromium || $chromium == *NOTFOUND* ]] || ! command -v "$chromium" >/dev/null 2>&1; then
  echo "SKIP: Chromium is not installed (Debian: apt-get install chromium; .ci/install-deps does it)"
  exit 77
fi

rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 2
echo "anima $*"
"$anima" "$@" >stdout.txt 2>stderr.txt
anima_status=$?
[[ $anima_status == 0 ]] || { cat stderr.txt; echo "FAIL: anima exited with $anima_status" >&2; exit 1; }
[[ -s $page ]] || { echo "FAIL: $page was not written" >&2; exit 1; }

flags=(--headless --no-first-run --no-default-browser-check --user-data-dir="$PWD/profile"
       --virtual-time-budget="$budget" --enable-logging=stderr --v=0 --window-size=1000,700)
# Chromium's sandbox refuses to run as root.
[[ $(id -u) == 0 ]] && flags+=(--no-sandbox)
if [[ $webgl == 1 ]]; then
  flags+=(--use-gl=angle --use-angle=swiftshader --enable-unsafe-swiftshader)
else
  flags+=(--disable-webgl --disable-3d-apis)
fi
timeout 60 "$chromium" "${flags[@]}" --dump-dom "file://$PWD/$page" >dom.html 2>chromium.txt
status=$?
fail=0
report() { echo "FAIL: $*" >&2; fail=1; }
[[ $status == 0 ]] || report "chromium exited with $status"

body=$(grep -o '<body[^>]*>' dom.html | head -n 1)
written=$(grep -o '<body[^>]*>' "$page" | head -n 1)
echo "page:    $written"
echo "browser: $body"
attribute() { sed -n "s/.* data-$1=\"\\([^\"]*\\)\".*/\\1/p" <<<"$2"; }

for e in "${equal[@]+"${equal[@]}"}"; do
  name=${e%%=*} want=${e#*=}
  got=$(attribute "$name" "$body")
  [[ $got == "$want" ]] || report "data-$name is '$got', expected '$want'"
done
for e in "${more[@]+"${more[@]}"}"; do
  name=${e%%=*} least=${e#*=}
  got=$(attribute "$name" "$body")
  awk -v g="$got" -v l="$least" 'BEGIN { exit !(g != "" && g + 0 == g && g + 0 > l + 0) }' ||
    report "data-$name is '$got', expected a number above $least"
done
for name in "${same[@]+"${same[@]}"}"; do
  got=$(attribute "$name" "$body") want=$(attribute "$name" "$written")
  [[ -n $got && $got == "$want" ]] || report "data-$name is '$got' in the browser, '$want' in the file"
done
error=$(attribute error "$body")
[[ -z $error ]] || report "the player stopped: $error"

# Console messages of the page. Chromium's own GL driver notes ("GPU stall
# due to ReadPixels", from software compositing) come through the same
# channel but are not the page's.
console=$(grep ':CONSOLE' chromium.txt | grep -v 'GL Driver Message' || true)
if [[ -n $console ]]; then
  echo "$console"
  report "the page logged to the console"
fi
exit $fail
