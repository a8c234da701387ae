# settings.sh - the architecture x setting matrix of bench/throughput.sh and
# bench/accuracy.sh (sourced). settings: paper = the shipped config
# (parasitic joints, inductive coil, rtol 1e-6, atol_scale 1e-3: the paper's
# model); exact-qs-1e-3 = the exact path at the setting issues 10 and 20
# measured (rigid, quasi-static coil, rtol 1e-3, natural tolerances);
# exact-recommended = what `pomlab tradeoff` recommends at 1 %
# (docs/tradeoff.md section 9: 3PSS and 3RRR inductive coil at rtol 1e-3,
# 3SPS quasi-static coil at rtol 1e-4); tight = the reference of any setting
# (setting_config ... tight BASE: BASE's model at rtol 1e-9, atol_scale 1e-6).
settings=("paper" "parasitic-quasi-static" "rigid-1e-6" "exact-qs-1e-3" "exact-recommended")
RIGID='s/^joints = {/joints = {\n  model = "rigid";/'
QS='s/^  coil_inductance = true;.*/  coil_inductance = false;/'
NATURAL='s/^  atol_scale = 1.0e-3;.*/  atol_scale = 0;/'
rtol_edit() { echo "s/^  rtol = 1.0e-6;.*/  rtol = $1;/"; }
edits_of() { # arch setting -> a sed script, one expression per line
  case "$2" in
  paper) echo "" ;;
  parasitic-quasi-static) echo "$QS" ;;
  rigid-1e-6) echo "$RIGID" ;;
  exact-qs-1e-3) printf '%s\n' "$RIGID" "$QS" "$NATURAL" "$(rtol_edit 1.0e-3)" ;;
  exact-recommended)
    if [ "$1" = 3sps ]; then
      printf '%s\n' "$RIGID" "$QS" "$NATURAL" "$(rtol_edit 1.0e-4)"
    else
      printf '%s\n' "$RIGID" "$NATURAL" "$(rtol_edit 1.0e-3)"
    fi
    ;;
  esac
}
n_of() { case "$1" in exact-*) echo $((10 * N)) ;; *) echo "$N" ;; esac }


# setting_config SRC ARCH SETTING [BASE] -> the config on stdout
setting_config() {
  local src=$1 arch=$2 setting=$3 base=${4:-}
  if [ "$setting" = tight ]; then
    {
      edits_of "$arch" "$base"
      echo 's/^  rtol = .*/  rtol = 1.0e-9;/'
      echo 's/^  atol_scale = .*/  atol_scale = 1.0e-6;/'
    } | sed -f - "$src/configs/$arch.cfg"
  else
    edits_of "$arch" "$setting" | sed -f - "$src/configs/$arch.cfg"
  fi
  # the 3-RRR's montecarlo draw needs a revolute range (docs/results.md)
  if [ "$arch" = 3rrr ]; then printf 'montecarlo = {\n  range_deg = 10.0;\n};\n'; fi
}
