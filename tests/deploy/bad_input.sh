# Sourced by the deploy tests: `bad NAME ARGS...` runs "$marsyn" ARGS and fails the test unless it
# exits with code 2 and one line on stderr starting "error: " (left in "$dir/err.txt").
bad() {
  name=$1; shift
  set +e
  "$marsyn" "$@" > /dev/null 2> "$dir/err.txt"
  rc=$?
  set -e
  [ $rc -eq 2 ] || fail "$name: exit code $rc, expected 2"
  [ "$(wc -l < "$dir/err.txt")" -eq 1 ] || fail "$name: not one line: $(cat "$dir/err.txt")"
  grep -q "^error: " "$dir/err.txt" || fail "$name: $(cat "$dir/err.txt")"
}
