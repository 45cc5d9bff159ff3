#!/usr/bin/env bash
# The SBST 2022 field on wogan's simulator: every peer generator in the competition's pipeline,
# under the competition's budgets, on both drivers (scripts/peers/README.md sets up PEERS_HOME).
#
#   PEERS_HOME=/path/to/peers scripts/peers/campaign.sh [ORACLES] [SEEDS] [TOOLS]
#   PEERS_HOME=~/peers scripts/peers/campaign.sh "beamng-ai-proxy dave2-proxy" "1 2 3"
#
# TOOLS: any of random freneticv ambiegen adafrenetic frenetic2021 (default: all). Each run is a
# result folder target/peers/ORACLE.TOOL.SEED/ (the pipeline's test.NNNN.json files, run.log,
# tests.jsonl, summary.json); a folder with a summary.json is kept, one without or whose summary
# names the signal that interrupted it is moved aside to target/peers/interrupted/ and run again.
# WOGAN=path uses another binary.
set -euo pipefail
cd "$(dirname "$0")/../.."
peers=${PEERS_HOME:?set PEERS_HOME to the folder holding venv/, pipeline/, pr/ and frenetic2021/}
oracles=${1:-beamng-ai-proxy dave2-proxy}
seeds=${2:-1 2 3}
tools=${3:-random freneticv ambiegen adafrenetic frenetic2021}
if [ -z "${WOGAN:-}" ]; then
  cargo build --release -q -p wogan-cli
  WOGAN=target/release/wogan
fi
out=target/peers
mkdir -p "$out/interrupted"

# The generator of each tool: pipeline checkout, then run_peer.py's options.
generator() {
  case "$1" in
    random) echo "pipeline --module-name sample_test_generators.random_generator --class-name RandomTestGenerator" ;;
    freneticv) echo "pr/107 --module-name frenetic.generators.frenetic_generator --class-name FreneticV" ;;
    ambiegen) echo "pr/108 --module-name ambiegen.ambiegen_generator --class-name AmbieGenTestGenerator" ;;
    adafrenetic) echo "pr/105 --module-name src.generators.adaptive_random_frenet_generator --class-name AdaFrenetic" ;;
    frenetic2021) echo "pipeline --api 2021 --module-path $peers/frenetic2021 --module-name src.generators.random_frenet_generator --class-name Frenetic" ;;
    *) echo "unknown tool '$1' (random freneticv ambiegen adafrenetic frenetic2021)" >&2; return 1 ;;
  esac
}

for oracle in $oracles; do
  for tool in $tools; do
    read -r checkout options <<< "$(generator "$tool")"
    for seed in $seeds; do
      folder="$out/$oracle.$tool.$seed"
      # A run cut short by a signal writes its summary too, naming the signal (run_peer.py's
      # json.dump spacing): it is run again.
      if [ -f "$folder/summary.json" ] && ! grep -q '"interrupted": "' "$folder/summary.json"; then
        continue
      fi
      if [ -d "$folder" ]; then mv "$folder" "$out/interrupted/$oracle.$tool.$seed.$(date +%s)"; fi
      # shellcheck disable=SC2086 # options are words
      "$peers/venv/bin/python" scripts/peers/run_peer.py --pipeline "$peers/$checkout" $options \
        --wogan "$WOGAN" --oracle "$oracle" --seed "$seed" --out "$folder" \
        > "$folder.log" 2>&1 || true
      if [ -f "$folder/summary.json" ]; then
        echo "$oracle $tool seed $seed: $(cut -c1-400 "$folder/summary.json")"
      else
        echo "$oracle $tool seed $seed: no summary (see $folder.log)" >&2
      fi
    done
  done
done
