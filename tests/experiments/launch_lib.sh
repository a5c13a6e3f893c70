#!/usr/bin/env bash
# launch_scripts/lib.sh, what the four launch scripts share: the URL rewriting (our options out of
# the URL for the evaluator and for lcm-spy), option parsing and the usage errors (exit 2 naming the
# option); and spy.sh's command line built on it (JAVA=echo prints the java command instead).
set -uo pipefail
repo=${REPO:-$(cd "$(dirname "$0")/../.." && pwd)}
fail=0
expect() {  # expect WHAT GOT WANTED
  if [ "$2" != "$3" ]; then
    echo "FAIL: $1: got '$2', wanted '$3'" >&2
    fail=1
  fi
}
prog=launch_lib
# shellcheck source=../../launch_scripts/lib.sh
source "$repo/launch_scripts/lib.sh"

expect plain "$(plain_lcm_url 'udpm://239.255.76.67:7667?ttl=0&channel_ports=1&recv_buf_size=5')" \
  'udpm://239.255.76.67:7667?ttl=0&recv_buf_size=5'
# The evaluator keeps receive=lcm (it asks our processes for liblcm's receive path)...
expect plain-keeps-receive "$(plain_lcm_url 'udpm://1.2.3.4:7667?channel_ports=1&receive=lcm&ttl=0')" \
  'udpm://1.2.3.4:7667?receive=lcm&ttl=0'
# ...lcm-spy gets neither of our options.
expect foreign "$(foreign_lcm_url 'udpm://1.2.3.4:7667?channel_ports=1&receive=lcm&ttl=0')" 'udpm://1.2.3.4:7667?ttl=0'
expect foreign-last "$(foreign_lcm_url 'udpm://1.2.3.4:7667?ttl=0&receive=lcm')" 'udpm://1.2.3.4:7667?ttl=0'
expect foreign-memq "$(foreign_lcm_url 'memq://')" 'memq://'

# --name value and --name=value.
split_option --jobs=3
option_value --jobs=3
expect inline "$opt $value $taken" '--jobs 3 0'
split_option --jobs
option_value --jobs 4
expect separate "$opt $value $taken" '--jobs 4 1'
# Usage errors: exit 2, the option named.
out=$( (split_option --jobs=; option_value --jobs=) 2>&1)
expect empty-code "$?" 2
expect empty-message "$(head -1 <<<"$out")" 'launch_lib: error: --jobs needs a non-empty value'
out=$( (check_count --jobs 0) 2>&1)
expect count-code "$?" 2
expect count-message "$(head -1 <<<"$out")" "launch_lib: error: --jobs must be an integer >= 1 (got '0')"
out=$( (check_choice --mode fast inprocess lockstep realtime) 2>&1)
expect choice-code "$?" 2
expect choice-message "$(head -1 <<<"$out")" \
  "launch_lib: error: --mode must be inprocess, lockstep or realtime (got 'fast')"
( check_count --jobs 5 && check_choice --mode lockstep inprocess lockstep realtime ) || expect good-values "$?" 0

# spy.sh: lcm-spy on the URL without our options, on a step channel's own port when asked.
spy() { DISPLAY=:0 JAVA=echo bash "$repo/launch_scripts/spy.sh" "$@" 2>/dev/null | tail -1; }
expect spy "$(spy --lcm-url 'udpm://239.255.76.67:7667?ttl=0&channel_ports=1&receive=lcm' | sed 's/.*--lcm-url //')" \
  'udpm://239.255.76.67:7667?ttl=0'
expect spy-step "$(spy --lcm-url 'udpm://239.255.76.67:7667?ttl=0&channel_ports=1' --step-channel STEP_REPLY |
  sed 's/.*--lcm-url //')" 'udpm://239.255.76.67:7669?ttl=0'
DISPLAY=:0 JAVA=echo bash "$repo/launch_scripts/spy.sh" --step-channel NOPE > /dev/null 2>&1
expect spy-bad-channel "$?" 2

# The default bus: the build's one definition (hunav_record --print-url), whatever the user's
# $LCM_DEFAULT_URL says; spy.sh watches it when told no URL.
bin_dir=${BIN:-$bin_dir}
default=$(LCM_DEFAULT_URL='memq://' default_lcm_url)
[[ $default == udpm://* ]] || expect default-url "$default" 'a udpm:// URL'
expect default-url-env-ignored "$(default_lcm_url)" "$default"
expect print-url-env "$(LCM_DEFAULT_URL='memq://' "$bin_dir/hunav_record" --print-url)" 'memq://'
expect print-url-flag "$("$bin_dir/hunav_record" --print-url --lcm-url 'udpm://1.2.3.4:7000')" 'udpm://1.2.3.4:7000'
expect spy-default "$(env -u LCM_DEFAULT_URL HUNAV_BIN_DIR="$bin_dir" DISPLAY=:0 JAVA=echo bash "$repo/launch_scripts/spy.sh" \
  2>/dev/null | tail -1 | sed 's/.*--lcm-url //')" "$(foreign_lcm_url "$default")"
expect url-option "$(with_url_option 'udpm://1.2.3.4:7000?ttl=0' channel_ports=1)" 'udpm://1.2.3.4:7000?ttl=0&channel_ports=1'
expect url-option-first "$(with_url_option 'udpm://1.2.3.4:7000' channel_ports=1)" 'udpm://1.2.3.4:7000?channel_ports=1'

[ "$fail" -eq 0 ] && echo "launch_lib: all checks passed"
exit "$fail"
