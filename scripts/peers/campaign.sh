#!/usr/bin/env bash
# The SBST 2022 field on wogan's simulator: every peer generator in the competition's pipeline,
# under the competition's budgets, on both drivers (scripts/peers/README.md sets up PEERS_HOME).
#
#   PEERS_HOME=/path/to/peers scripts/peers/campaign.sh [ORACLES] [SEEDS] [TOOLS]
#   PEERS_HOME=~/peers scripts/peers/campaign.sh "beamng-ai-proxy dave2-proxy" "1 2 3"
#   PEERS_HOME=~/peers scripts/peers/campaign.sh "metadrive-idm metadrive-expert" "1 2 3"
#
# ORACLES: wogan's drivers, or metadrive-idm / metadrive-expert: MetaDrive's executor
# (examples/metadrive/, after its setup.sh) with that policy, at wogan's default conditions (0.85
# tolerance, 70 km/h), answering with the pipeline's execution data. SPEED_LIMIT=46 drives at 46
# km/h instead (MetaDrive's IDM calibrated: examples/metadrive/README.md); its folders are named
# ORACLE@46.TOOL.SEED.
# TOOLS: any of random freneticv ambiegen adafrenetic frenetic2021 (default: all). Each run is a
# result folder target/peers/ORACLE.TOOL.SEED/ (the pipeline's test.NNNN.json files, run.log,
# tests.jsonl, summary.json); a folder with a summary.json is kept, one without or whose summary
# names the signal that interrupted it is moved aside to target/peers/interrupted/ and run again.
# Each tool runs in the Python environment of its competition's year (setup.sh): Frenetic (2021)
# in venv-2021, the others in venv.
# A run the generator's exception ended is named on stderr as it ends and again at the end
# (crashes.py): as the tool's own behaviour in its competition where crashes.py knows it so, as a
# harness defect otherwise, and then the campaign exits 1.
# WOGAN=path uses another binary.
set -euo pipefail
cd "$(dirname "$0")/../.."
peers=${PEERS_HOME:?set PEERS_HOME to the folder setup.sh made (venv/, venv-2021/, pipeline/, pr/, frenetic2021/)}
oracles=${1:-beamng-ai-proxy dave2-proxy}
seeds=${2:-1 2 3}
tools=${3:-random freneticv ambiegen adafrenetic frenetic2021}
if [ -z "${WOGAN:-}" ]; then
  cargo build --release -q -p wogan-cli
  WOGAN=target/release/wogan
fi
out=target/peers
metadrive_python=target/metadrive-venv/bin/python
case " $oracles " in
  *" metadrive-"*) [ -x "$metadrive_python" ] || { echo "campaign.sh: no $metadrive_python: run examples/metadrive/setup.sh" >&2; exit 2; } ;;
esac
mkdir -p "$out/interrupted"

# The generator of each tool: its Python environment, pipeline checkout, then run_peer.py's options.
generator() {
  case "$1" in
    random) echo "venv pipeline --module-name sample_test_generators.random_generator --class-name RandomTestGenerator" ;;
    freneticv) echo "venv pr/107 --module-name frenetic.generators.frenetic_generator --class-name FreneticV" ;;
    ambiegen) echo "venv pr/108 --module-name ambiegen.ambiegen_generator --class-name AmbieGenTestGenerator" ;;
    adafrenetic) echo "venv pr/105 --module-name src.generators.adaptive_random_frenet_generator --class-name AdaFrenetic" ;;
    frenetic2021) echo "venv-2021 pipeline --api 2021 --module-path $peers/frenetic2021 --module-name src.generators.random_frenet_generator --class-name Frenetic" ;;
    *) echo "unknown tool '$1' (random freneticv ambiegen adafrenetic frenetic2021)" >&2; return 1 ;;
  esac
}

for oracle in $oracles; do
  for tool in $tools; do
    read -r venv checkout options <<< "$(generator "$tool")"
    for seed in $seeds; do
      folder="$out/$oracle${SPEED_LIMIT:+@$SPEED_LIMIT}.$tool.$seed"
      # A run cut short by a signal writes its summary too, naming the signal (run_peer.py's
      # json.dump spacing): it is run again.
      if [ -f "$folder/summary.json" ] && ! grep -q '"interrupted": "' "$folder/summary.json"; then
        continue
      fi
      if [ -d "$folder" ]; then mv "$folder" "$out/interrupted/$oracle.$tool.$seed.$(date +%s)"; fi
      # The driver: wogan's simulator, or MetaDrive's executor for metadrive-POLICY.
      case "$oracle" in
        metadrive-*) drive=(--executor "$metadrive_python examples/metadrive/executor.py --policy ${oracle#metadrive-} --execution-data --log-level WARNING") ;;
        *) drive=(--wogan "$WOGAN") ;;
      esac
      # shellcheck disable=SC2086 # options are words
      "$peers/$venv/bin/python" scripts/peers/run_peer.py --pipeline "$peers/$checkout" $options \
        "${drive[@]}" ${SPEED_LIMIT:+--speed-limit "$SPEED_LIMIT"} --oracle "$oracle" --seed "$seed" --out "$folder" \
        > "$folder.log" 2>&1 || true
      if [ -f "$folder/summary.json" ]; then
        echo "$oracle $tool seed $seed: $(cut -c1-400 "$folder/summary.json")"
        python3 scripts/peers/crashes.py --quiet "$folder" || true
      else
        echo "$oracle $tool seed $seed: no summary (see $folder.log)" >&2
      fi
    done
  done
done

# Every crashed run of these tools, drivers and seeds, old or new: exit 1 if any is the harness's.
folders=()
for oracle in $oracles; do
  for tool in $tools; do
    for seed in $seeds; do
      [ -f "$out/$oracle.$tool.$seed/summary.json" ] && folders+=("$out/$oracle.$tool.$seed")
    done
  done
done
[ ${#folders[@]} -eq 0 ] || python3 scripts/peers/crashes.py "${folders[@]}"
