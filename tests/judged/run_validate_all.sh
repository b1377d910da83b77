#!/usr/bin/env bash
# validate --all with the given options, its rows then held to their judged
# lines (judged_property.py): the table must pass, and every row's verdict must
# be what its check's judgement says. Usage: run_validate_all.sh VALIDATE OUT_DIR [OPTIONS...]
set -euo pipefail
validate=$1
out=$2
shift 2
mkdir -p "$out"
"$validate" --all --color never --json "$out/validate_all.json" "$@"
python3 "$(dirname "$0")/judged_property.py" "$out/validate_all.json"
