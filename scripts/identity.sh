#!/usr/bin/env bash
# Output identity check: the md5s that a change meant to keep behaviour
# (a refactor, a speed-up) must leave as they are. Prints one line a check;
# compare with scripts/identity.expected (`diff <(scripts/identity.sh) scripts/identity.expected`).
# Usage: scripts/identity.sh [path/to/fixplan]   (default: target/ci/fixplan-it, the
# integration tests' copy of the CLI, built with CI's features, so no second
# zenoh build)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/ci/fixplan-it}
if [ ! -x "$bin" ]; then
  cargo build --profile ci --locked -p fixplan-tests --features fixplan-tests/tls --bin fixplan-it >&2
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" run -o "$tmp/sample.mcap" >/dev/null 2>&1
echo "sample-export $("$bin" export "$tmp/sample.mcap" --json | md5sum | cut -d' ' -f1)"
"$bin" run --catalog examples/catalog-inch -o "$tmp/inch.mcap" >/dev/null 2>&1
echo "inch-export $("$bin" export "$tmp/inch.mcap" --json | md5sum | cut -d' ' -f1)"
for case in examples/cases/*.json; do
  name=$(basename "$case" .json)
  echo "case-$name $("$bin" solve "$case" 2>/dev/null | md5sum | cut -d' ' -f1)"
  echo "case-$name-top0 $("$bin" solve "$case" --full-counts 2>/dev/null | md5sum | cut -d' ' -f1)"
done
