# Sourced by the command-line tests: a scratch directory, removed at exit,
# and the count of failed checks.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

# after_stepping_starts LOG SECONDS [PID]: returns SECONDS (times
# GRANFLOW_SLOWDOWN, for instrumented builds) after a run started with
# --log has printed its table's header to LOG, which it does once its
# initial state is ready: a signal sent then lands in the stepping however
# long the preparation took. Gives up waiting if process PID ends.
after_stepping_starts() {
  local log="$1" delay="$2" pid="${3:-}"
  for _ in $(seq 1 3000); do
    grep -q '^ *step ' "$log" 2> /dev/null && break
    [[ -n "$pid" ]] && ! kill -0 "$pid" 2> /dev/null && break
    sleep 0.02
  done
  sleep "$(awk -v d="$delay" -v s="${GRANFLOW_SLOWDOWN:-1}" 'BEGIN { print d * s }')"
}
