#!/usr/bin/env bash
# Fetches the five ETH/UCY pedestrian recordings hunav_realism scores the people models on
# (realism/README.md, "Data") into DIR, and checks each file's SHA-256 against the copy the project's
# numbers were measured on. They are not in the repository: no licence is stated for the ETH (BIWI)
# recordings, and the UCY ones are for research use with credit (cite the papers below).
#
#   tools/fetch_eth_ucy.sh DIR        e.g. tools/fetch_eth_ucy.sh ../shared/eth_ucy
#
# Source: StanfordASL/Trajectron-plus-plus at commit 1031c7bd1a444273af378c1ec1dcca907ba59830,
# experiments/pedestrians/raw/raw/all_data/ (the Social-LSTM / Social-GAN benchmark files; format
# `frame id x y`, tab separated, metres). HUNAV_ETH_UCY_URL replaces the base URL (a mirror, or a
# file:// folder). Cite S. Pellegrini, A. Ess, K. Schindler, L. Van Gool, "You'll never walk alone:
# Modeling social behavior for multi-target tracking", ICCV 2009 (ETH, Hotel), and A. Lerner,
# Y. Chrysanthou, D. Lischinski, "Crowds by example", Computer Graphics Forum 26(3), 2007 (Zara, Univ).
# Exit 0: every file there and checked; 1: a download failed or a file differs; 2: bad arguments.
set -euo pipefail

if [ "$#" -ne 1 ] || [ "${1:-}" = -h ] || [ "${1:-}" = --help ]; then
  sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
  [ "$#" -eq 1 ] && exit 0 || exit 2
fi
dir=$1
base=${HUNAV_ETH_UCY_URL:-https://raw.githubusercontent.com/StanfordASL/Trajectron-plus-plus/1031c7bd1a444273af378c1ec1dcca907ba59830/experiments/pedestrians/raw/raw/all_data}
# name and SHA-256 of each file.
files=(
  "biwi_eth.txt cf8d3fd342a15f409ebc2a1fc76b91a0f06390bd21f1e11410f3859331ab082b"
  "biwi_hotel.txt 9caa771bb9153d6b809dd0916b6f86761b641e6bbb15e766c1de3133fbbb7fcf"
  "crowds_zara01.txt 1147a1962a09abfb86f28c6cddcac862e095a0cf129b3016385b69eacdd09d85"
  "crowds_zara02.txt 8a649d0f8c9ae75c87c4d23a85f892786b0aa30266e996c7be03e69dafff22ff"
  "students003.txt e25798b660634330aa89f8bb259425de720e84d0873902726c1d1f4ccff21d6c"
)
mkdir -p "$dir" || { echo "fetch_eth_ucy: cannot create '$dir'" >&2; exit 2; }
command -v curl >/dev/null 2>&1 || { echo "fetch_eth_ucy: needs curl (apt-get install curl)" >&2; exit 1; }
status=0
for entry in "${files[@]}"; do
  name=${entry%% *} sum=${entry#* }
  target="$dir/$name"
  if [ -f "$target" ] && echo "$sum  $target" | sha256sum --check --status; then
    echo "fetch_eth_ucy: $target: present, checked"
    continue
  fi
  if ! curl --fail --silent --show-error --location --output "$target.part" "$base/$name"; then
    echo "fetch_eth_ucy: $base/$name: download failed" >&2
    rm -f "$target.part"
    status=1
    continue
  fi
  if ! echo "$sum  $target.part" | sha256sum --check --status; then
    echo "fetch_eth_ucy: $base/$name: its SHA-256 is not $sum (not the file the project's numbers are measured on); left as $target.part" >&2
    status=1
    continue
  fi
  mv "$target.part" "$target"
  echo "fetch_eth_ucy: $target: fetched, checked"
done
exit "$status"
