#!/usr/bin/env bash
# Summarises hard_warps tables (the output of `hard_warps ... --color never`,
# one file per seed) as markdown rows: each (case, check) with a row that did
# not pass on some seed, or passed saying what run_hard.sh forbids (tested
# nothing; a NaN figure), with the number of seeds and the first message (cut
# to 300 characters). Used for tests/hard/BASELINE.md:
#   for k in $(seq 1 10); do hard_warps --all --seed $k --color never > seed$k.txt; done
#   tests/hard/summarise.sh seed*.txt
# Usage: summarise.sh TABLE...
set -euo pipefail
rows=$(awk -v files=$# '
  function note(key, text) { count[key]++; if (!(key in message)) message[key] = substr(text, 1, 300) }
  /^(FAIL|ERROR) / { seen[$3 "|" $2 "|" $1] = 1 }
  /^pass / {
    summary = $0; sub(/^pass +[^ ]+ +[^ ]+ +/, "", summary)
    if (summary ~ /^not applicable/) note($3 "|" $2 "|pass, tested nothing", summary)
    else if (tolower(summary) ~ /(^|[^a-z])nan([^a-z]|$)/) note($3 "|" $2 "|pass, NaN figure", summary)
  }
  /^  (FAIL|ERROR) / {
    line = $0; sub(/^  /, "", line)
    verdict = line; sub(/ .*/, "", verdict)
    check = line; sub(/^[^ ]+ /, "", check); sub(/ .*/, "", check)
    name = line; sub(/^[^ ]+ [^ ]+ /, "", name); sub(/: .*/, "", name)
    text = line; sub(/^[^:]*: /, "", text)
    if ((name "|" check "|" verdict) in seen) note(name "|" check "|" verdict, text)
  }
  END {
    for (k in count) {
      split(k, f, "|")
      m = message[k]; gsub(/[|]/, "\\|", m)
      printf "| %s | %s | %s | %d/%d | %s |\n", f[1], f[2], f[3], count[k], files, m
    }
  }' "$@" | sort)
echo "| case | check | verdict | seeds | first message |"
echo "| --- | --- | --- | --- | --- |"
echo "$rows"
