#!/usr/bin/env bash
# Sets up PEERS_HOME for scripts/peers (dev-time; README.md beside this file): the competition's
# pipeline, the three 2022 tools' pull requests, Frenetic (2021), and one Python environment per
# competition year, so that each tool runs with the libraries it ran with in its competition.
#
#   PEERS_HOME=~/peers scripts/peers/setup.sh
#   PEERS_HOME=~/peers PIPELINE_REPO=/path/to/tool-competition-av FRENETIC2021_REPO=/path/to/frenetic-sbst21 \
#       scripts/peers/setup.sh          # from local clones instead of GitHub
#
# It makes (and leaves what is already there):
#   pipeline/  pr/105/ pr/107/ pr/108/   the pipeline's main branch and the 2022 submissions'
#                                        pull requests (AdaFrenetic, FreneticV, AmbieGen)
#   frenetic2021/                        Frenetic, as submitted to SBST 2021
#   venv/        Python 3.11             the 2022 tools and the pipeline's random generator
#   venv-2021/   Python 3.7              Frenetic (2021): the pandas of its submission (1.2.2,
#                                        February 2021) and the numpy and scipy of its requirements
# and checks that each environment gives its year's answer to the one pandas call whose
# behaviour changed under the tools (check_envs.py).
#
# The model files (dave2/) and BeamNG's level (levels_template/) are left out: no tool here uses
# them, and they are the largest files of the repositories. PYTHON_2021 names the Python 3.7
# interpreter when `python3.7` is not on the PATH (pyenv's is found).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
peers=${PEERS_HOME:?set PEERS_HOME to the folder to set up (for example ~/peers)}
pipeline_repo=${PIPELINE_REPO:-https://github.com/se2p/tool-competition-av}
frenetic_repo=${FRENETIC2021_REPO:-https://github.com/ERATOMMSD/frenetic-sbst21}
mkdir -p "$peers"
cd "$peers"

# A tree of REPO's COMMIT in FOLDER, without the large files no tool needs.
extract() {
  local git_dir=$1 commit=$2 folder=$3
  [ -d "$folder" ] && return
  mkdir -p "$folder.partial"
  git -C "$git_dir" archive "$commit" -- . ':(exclude)dave2' ':(exclude)levels_template' \
    | tar -x -C "$folder.partial"
  mv "$folder.partial" "$folder"
}

if [ ! -d pipeline.git ]; then
  git clone -q --bare "$pipeline_repo" pipeline.git.partial
  # The 2022 submissions were pull requests to the pipeline.
  git -C pipeline.git.partial fetch -q origin \
    refs/pull/105/head:refs/pr/105 refs/pull/107/head:refs/pr/107 refs/pull/108/head:refs/pr/108
  mv pipeline.git.partial pipeline.git
fi
extract pipeline.git HEAD pipeline
for n in 105 107 108; do extract pipeline.git "refs/pr/$n" "pr/$n"; done
if [ ! -d frenetic2021.git ]; then
  git clone -q --bare "$frenetic_repo" frenetic2021.git.partial
  mv frenetic2021.git.partial frenetic2021.git
fi
extract frenetic2021.git HEAD frenetic2021

# 2022: the pins the pipeline and the 2022 tools need (Shapely 1.8's API, pandas before 2 for
# FreneticV's DataFrame.append, pymoo 0.4 for AmbieGen).
# (A venv is ready once its .ready file is written; a half-made one is made again.)
if [ ! -f venv/.ready ]; then
  rm -rf venv
  python3.11 -m venv venv
  venv/bin/pip install -q numpy==1.23.5 scipy==1.9.3 shapely==1.8.5.post1 \
    matplotlib==3.6.3 click descartes pandas==1.5.3 pymoo==0.4.2.2
  touch venv/.ready
fi

# 2021: Frenetic's requirements-37.txt names numpy 1.19.3 and scipy 1.5.4 and leaves pandas
# unpinned; it was submitted on 2021-02-12, when pandas 1.2.2 was the newest. Shapely is the
# pipeline's (the validator every tool meets is the 2022 pipeline's, with the same verdicts).
if [ ! -f venv-2021/.ready ]; then
  rm -rf venv-2021
  # The first candidate that runs and is 3.7 (pyenv's shim for a version not selected does not).
  python_2021=""
  for candidate in ${PYTHON_2021:-} python3.7 "$HOME"/.pyenv/versions/3.7*/bin/python3.7; do
    if "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 7))' 2> /dev/null; then
      python_2021=$candidate
      break
    fi
  done
  [ -n "$python_2021" ] || { echo "setup.sh: no Python 3.7 found: set PYTHON_2021" >&2; exit 2; }
  "$python_2021" -m venv venv-2021
  venv-2021/bin/pip install -q numpy==1.19.3 scipy==1.5.4 pandas==1.2.2 \
    shapely==1.8.5.post1 matplotlib==3.0.3 click==7.1.2 descartes==1.1.0
  touch venv-2021/.ready
fi

venv/bin/python "$here/check_envs.py" 2022
venv-2021/bin/python "$here/check_envs.py" 2021
echo "setup.sh: $peers is ready"
