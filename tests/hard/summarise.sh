#!/usr/bin/env bash
# Summarises hard_warps tables (the output of `hard_warps ... --color never`,
# one file per seed) as markdown rows: for each (case, check) that did not pass
# on some seed, the verdicts with their seed counts and the first message
# (cut to 300 characters). Used for tests/hard/BASELINE.md:
#   for k in $(seq 1 10); do hard_warps --all --seed $k --color never > seed$k.txt; done
#   tests/hard/summarise.sh seed*.txt
# Usage: summarise.sh TABLE...
set -euo pipefail
rows=$(awk -v files=$# '
  FNR == 1 { ++file }
  /^(FAIL|ERROR) / { key = $3 " | " $2; count[key, $1]++; keys[key] = 1 }
  /^  (FAIL|ERROR) / {
    line = $0; sub(/^  (FAIL|ERROR) /, "", line)
    split(line, parts, ": "); check = parts[1]; sub(/ .*/, "", check)
    name = parts[1]; sub(/^[^ ]+ /, "", name)
    key = name " | " check
    if (!(key in message)) { m = substr(line, length(parts[1]) + 3); message[key] = substr(m, 1, 300) }
  }
  END {
    for (k in keys) {
      split(k, kc, " [|] ")
      gsub(/[|]/, "\\|", message[k])
      printf "| %s | %s | %d/%d | %d/%d | %s |\n", kc[1], kc[2], count[k, "FAIL"], files, count[k, "ERROR"], files, message[k]
    }
  }' "$@" | sort)
echo "| case | check | FAIL | ERROR | first message |"
echo "| --- | --- | --- | --- | --- |"
echo "$rows"
