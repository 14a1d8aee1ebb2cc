# Sourced by the CLI tests. expect CODE PATTERN -- command...: the command (killed after
# $expect_timeout seconds, 60 by default) must exit with CODE and print PATTERN (stdout or stderr);
# a miss prints the output's tail and sets failed=1.
expect() {
  local code=$1 pattern=$2
  shift 3
  local out rc
  out=$(timeout -s KILL "${expect_timeout:-60}" "$@" 2>&1)
  rc=$?
  if [ "$rc" -ne "$code" ] || ! grep -qF -- "$pattern" <<<"$out"; then
    echo "FAIL: '$*' exited $rc (want $code), output:"
    echo "$out" | sed 's/^/    /' | tail -n 8
    failed=1
  else
    echo "ok: '$*' -> $rc: $(grep -F -- "$pattern" <<<"$out" | head -n 1)"
  fi
}
