#!/bin/sh
# Rules outside the core (plastivox/rules/life_rules.hpp): simulate() measures a life and
# judge_life decides whether it counts. Every source outside the core that calls simulate()
# calls judge_life too, or marks each call "not judged" (a life simulated for its frames or
# its timing only). Prints the unjudged calls and fails when there are any. Run from the
# repository's top.
found=0
for f in $(grep -rlE '(^|[^_a-z.])simulate\(' engine/evo engine/io analysis apps render/files \
             python/src --include=*.cpp); do
  grep -q judge_life "$f" && continue
  calls=$(grep -nE '(^|[^_a-z.])simulate\(' "$f" | grep -v 'not judged' | grep -vE '^[0-9]+: *//')
  if [ -n "$calls" ]; then
    echo "$calls" | sed "s|^|$f:|"
    found=1
  fi
done
exit $found
