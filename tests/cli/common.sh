# Sourced by the command-line tests: a scratch directory, removed at exit,
# and the count of failed checks.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
