#!/usr/bin/env bash
# test_output_paths.sh - outputs never overwrite inputs or each other (issue
# 22, items 2 and 20): every command with an output flag refuses, with exit 2
# and before any work, an output that is the same file as its config, a file
# the config includes, a candidate's config or another output of the run (by
# device and inode, or by resolved path where it does not exist yet); the
# tabular file's name rule; codesign's results file, figure, journal and lock
# against its inputs (issue 29, item 2); --tabular makes its folder like --out, and a
# folder it cannot write is refused before the work.
# Usage: test_output_paths.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

cd "$TMP" || exit 1
# the inputs: a study with an @include, its candidate's config, a
# sensitivity file (made again where a section must not depend on the ones
# before it having held)
make_inputs() {
  cp "$SRC/configs/3pss.cfg" cand.cfg
  printf 'montecarlo = { maneuvers = 2; seed = 3; };\n' >inc.cfg
  cat >S.cfg <<CFG
name = "paths";
@include "inc.cfg"
study = { threads = 1; override = { joints = { model = "rigid"; };
  scene = { coil_inductance = false; }; }; };
candidates = ( { name = "A"; config = "cand.cfg"; } );
CFG
  # a sensitivity file: the same study with one uncertain parameter, 4 samples
  cat >U.cfg <<CFG
@include "S.cfg"
uncertain = ( { key = "actuator.resistance_ohm"; dist = "uniform"; min = 9.0; max = 11.0;
  relative = false; } );
sensitivity = { method = "sobol"; samples = 4; maneuvers = 1; bootstrap = 10; };
CFG
}
make_inputs
sums() { md5sum S.cfg inc.cfg cand.cfg U.cfg r.h5 2>/dev/null; }
# refused DESCRIPTION TEXT CMD...: exit 2, TEXT on stderr, no file changed
refused() {
  local what=$1 text=$2
  shift 2
  local before
  before=$(sums)
  expect_rc 2 "$@"
  expect_err "$text"
  check "$what: inputs and earlier results untouched" [ "$before" = "$(sums)" ]
}
STUDY=("$POMLAB" study S.cfg --quiet --no-plots --no-summary)

# a first run leaves results r.h5 that a refused run must not replace
expect_rc 0 "${STUDY[@]}" --out r.h5
check "first run wrote r.h5" [ -s r.h5 ]

# --- item 2: the issue's cases -------------------------------------------------
refused "--tabular = --out" "the tabular file (--tabular) 'r.h5' is the same file as the results file (--out) 'r.h5'" \
  "${STUDY[@]}" --out r.h5 --tabular r.h5
refused "--out = config" "the results file (--out) 'S.cfg' is the same file as the config 'S.cfg'" \
  "${STUDY[@]}" --out S.cfg
refused "--tabular = config" "'S.cfg' is the same file as the config 'S.cfg'" \
  "${STUDY[@]}" --out r2.h5 --tabular S.cfg
refused "--tabular = candidate config" "is the same file as the config of candidate 'A' 'cand.cfg'" \
  "${STUDY[@]}" --out r2.h5 --tabular cand.cfg
refused "--out = included file" "is the same file as a file included by the config" \
  "${STUDY[@]}" --out inc.cfg
refused "sensitivity --out = config" "pomlab sensitivity: the results file (--out) 'U.cfg' is the same file as the config" \
  "$POMLAB" sensitivity U.cfg --out U.cfg --quiet --no-plots
refused "sensitivity --out = a file the config includes" "a file included by the config" \
  "$POMLAB" sensitivity U.cfg --out S.cfg --quiet --no-plots
check "nothing made beside the refused runs" [ ! -e r2.h5 ] && [ ! -e r2.h5.partial ]
# links: the same inode, or the same file through a symbolic link
ln -s S.cfg sym.h5
ln cand.cfg hard.h5
refused "--out is a symbolic link to the config" "'sym.h5' is the same file as the config" \
  "${STUDY[@]}" --out sym.h5
refused "--out is a hard link of the candidate's config" "'hard.h5' is the same file as the config of candidate 'A'" \
  "${STUDY[@]}" --out hard.h5
# two outputs that do not exist yet: the same resolved path
refused "two new outputs, one path" "the tabular file (--tabular) 'new.csv' is the same file as the results file (--out) 'nosuch/../new.csv'" \
  "${STUDY[@]}" --out nosuch/../new.csv --tabular new.csv
refused "the candidates table = the results file" "the candidates table (--tabular) 'q_candidates.csv' is the same file as the results file" \
  "${STUDY[@]}" --out q_candidates.csv --tabular q.csv
refused "the results file = the summary" "is the same file as the summary 'o/summary.md'" \
  "$POMLAB" study S.cfg --quiet --no-plots --out o.h5 --tabular o/summary.md
# the results' lock (OUTPUT.lock, truncated when taken): a config of that name
cp S.cfg SL.h5.lock
before_l=$(md5sum SL.h5.lock)
expect_rc 2 "$POMLAB" study SL.h5.lock --quiet --no-plots --no-summary --out SL.h5
expect_err "the lock file 'SL.h5.lock' is the same file as the config 'SL.h5.lock'"
check "study: a config named like the lock untouched" [ "$before_l" = "$(md5sum SL.h5.lock)" ]
check "study: nothing made beside the refused lock run" [ ! -e SL.h5 ]
# montecarlo, simulate, tradeoff, workspace, tune, synth
refused "montecarlo --out = config" "pomlab montecarlo: the results file (--out) 'cand.cfg' is the same file as the config" \
  "$POMLAB" montecarlo cand.cfg --n 1 --out cand.cfg --quiet
refused "montecarlo --tabular = --out" "the tabular file (--tabular) 'm.csv' is the same file as the results file (--out) 'm.csv'" \
  "$POMLAB" montecarlo cand.cfg --n 1 --out m.csv --tabular m.csv --quiet
ln -s cand.cfg trace.csv
refused "simulate --out = config" "pomlab simulate: the traces (--out) 'trace.csv' is the same file as the config" \
  "$POMLAB" simulate cand.cfg --target 1,1,1 --out trace.csv
refused "tradeoff --csv = config" "pomlab tradeoff: the table (--csv) 'cand.cfg' is the same file as the config" \
  "$POMLAB" tradeoff cand.cfg --csv cand.cfg --quiet
refused "workspace --map = config" "pomlab workspace: the map (--map) 'cand.cfg' is the same file as the config" \
  "$POMLAB" workspace cand.cfg --map cand.cfg --quiet
STEM=3PSS_reference_isotropic_at_home_sigma_15_mm
cp cand.cfg "t_$STEM.controller.cfg"
sums_t() { md5sum "t_$STEM.controller.cfg"; }
before=$(sums_t)
expect_rc 2 "$POMLAB" tune "t_$STEM.controller.cfg" --out t_ --quiet
expect_err "pomlab tune: the gains file (--out PREFIX + name) 't_$STEM.controller.cfg' is the same file as the config"
check "tune: config untouched" [ "$before" = "$(sums_t)" ]
cp cand.cfg "s_$STEM.geometry.cfg"
sed "s|@include \"3pss.cfg\"|@include \"s_$STEM.geometry.cfg\"|" "$SRC/configs/synth_3pss.cfg" >syn.cfg
expect_rc 2 "$POMLAB" synth syn.cfg --out s_ --quiet
expect_err "pomlab synth: the geometry file (--out PREFIX + name) 's_$STEM.geometry.cfg' is the same file as a file included by the config"

# --- codesign (issue 29, item 2): the study's rule for every file it writes ---
# the results file, its figure (R.svg), the resume journal (R.h5.journal) and
# the lock (R.h5.lock) against the codesign file, a file it includes and
# every candidate's config; refused before the lock or the journal is made
cp "$SRC/configs/3pss.cfg" cand.cfg
printf 'uncertain = ( { key = "actuator.resistance_ohm"; dist = "uniform"; min = 0.95; max = 1.05; relative = true; } );\n' >cds_inc.cfg
# codesign_file NAME [OUTPUT]: a small co-design of cand.cfg (as test_codesign.sh's)
codesign_file() {
  cat >"$1" <<CFG
name = "small";
montecarlo = { maneuvers = 2; seed = 11; space = "orientation"; tilt_max_deg = 6.0; torsion_max_deg = 6.0; };
@include "cds_inc.cfg"
codesign = {
  output = "${2:-cds.h5}";
  threads = 1;
  requirements = { workspace_half_width_deg = 8.0; dexterity_min = 0.3; current_limit_A = 3.0;
                   envelope_radius_mm = 150.0; time_max_ms = 40.0; };
  optimizer = { max_evals = 2; starts = 1; };
  front_points = 2;
  reevaluate = { seed = 12; maneuvers = 2; };
};
candidates = ( { name = "A"; config = "cand.cfg";
  variables = ( { key = "size"; min = 0.6; max = 1.6; },
                { key = "controller.kp"; min = 3.0e3; max = 3.0e4; log = true; } ); } );
CFG
}
codesign_file small.cfg
codesign_file D.svg
codesign_file J.h5.journal
codesign_file L.h5.lock
codesign_file O.cfg O.cfg
sums_c() { md5sum small.cfg cds_inc.cfg cand.cfg D.svg J.h5.journal L.h5.lock O.cfg; }
# refused_c DESCRIPTION TEXT ARGS...: exit 2, TEXT on stderr, every input's
# bytes unchanged and nothing made (no results file, figure, journal, lock)
refused_c() {
  local what=$1 text=$2
  shift 2
  local before files
  before=$(sums_c)
  files=$(ls -A)
  expect_rc 2 "$POMLAB" codesign "$@" --quiet
  expect_err "pomlab codesign: $text"
  check "codesign $what: inputs untouched" [ "$before" = "$(sums_c)" ]
  check "codesign $what: nothing made" [ "$files" = "$(ls -A)" ]
}
refused_c "--out = config" "the results file (--out) 'small.cfg' is the same file as the config 'small.cfg'" \
  small.cfg --out small.cfg
refused_c "--out = candidate config" "the results file (--out) 'cand.cfg' is the same file as the config of candidate 'A'" \
  small.cfg --out cand.cfg
refused_c "--out = included file" "the results file (--out) 'cds_inc.cfg' is the same file as a file included by the config" \
  small.cfg --out cds_inc.cfg
refused_c "the figure = config" "the figure 'D.svg' is the same file as the config 'D.svg'" \
  D.svg --out D.h5
refused_c "the journal = config" "the resume journal 'J.h5.journal' is the same file as the config 'J.h5.journal'" \
  J.h5.journal --out J.h5
refused_c "the journal = config, --resume" "the resume journal 'J.h5.journal' is the same file as the config" \
  J.h5.journal --out J.h5 --resume
refused_c "the lock = config" "the lock file 'L.h5.lock' is the same file as the config 'L.h5.lock'" \
  L.h5.lock --out L.h5
refused_c "codesign.output = config" "the results file (codesign.output) 'O.cfg' is the same file as the config 'O.cfg'" \
  O.cfg
ln -s small.cfg cds_sym.h5
refused_c "--out a symbolic link to the config" "the results file (--out) 'cds_sym.h5' is the same file as the config 'small.cfg'" \
  small.cfg --out cds_sym.h5
ln cand.cfg cds_hard.h5
refused_c "--out a hard link of the candidate's config" "the results file (--out) 'cds_hard.h5' is the same file as the config of candidate 'A'" \
  small.cfg --out cds_hard.h5

# --- item 2: the tabular name rule -------------------------------------------
refused "--tabular F_candidates.csv" "--tabular 'F_candidates.csv': a name ending in _candidates.csv is the candidates table of another name" \
  "${STUDY[@]}" --out r2.h5 --tabular F_candidates.csv
check "no F_candidates_candidates.csv" [ ! -e F_candidates_candidates.csv ]
refused "--tabular /dev/stdout" "--tabular '/dev/stdout': expected a file name ending in .csv" \
  "${STUDY[@]}" --out r2.h5 --tabular /dev/stdout
check "no /dev/stdout_candidates.csv" [ ! -e /dev/stdout_candidates.csv ]
mkfifo fifo.csv
refused "--tabular a FIFO" "--tabular 'fifo.csv' is not a regular file" \
  "${STUDY[@]}" --out r2.h5 --tabular fifo.csv
refused "--tabular without .csv" "--tabular 'table.txt': expected a file name ending in .csv" \
  "${STUDY[@]}" --out r2.h5 --tabular table.txt
printf 'name = "paths";\n@include "inc.cfg"\nstudy = { tabular = "T_candidates.csv"; };\n%s\n' \
  'candidates = ( { name = "A"; config = "cand.cfg"; } );' >ST.cfg
expect_rc 2 "$POMLAB" study ST.cfg --out r2.h5 --quiet --no-plots
expect_err "study.tabular 'T_candidates.csv': a name ending in _candidates.csv"
check "nothing made by the refused runs" [ ! -e r2.h5 ] && [ ! -e r2.h5.partial ]

# --- item 20: --tabular makes its folder, or is refused before the work -------
make_inputs
expect_rc 0 "${STUDY[@]}" --out r3.h5 --tabular new/deeper/t.csv
check "--tabular made its folders" [ -s new/deeper/t.csv ] && [ -s new/deeper/t_candidates.csv ]
touch afile
expect_rc 1 "${STUDY[@]}" --out r4.h5 --tabular afile/t.csv
expect_err "--tabular 'afile/t.csv': cannot create folder 'afile'"
check "refused before the work: no results file" [ ! -e r4.h5 ] && [ ! -e r4.h5.partial ]
mkdir ro && chmod 555 ro
if [ ! -w ro ]; then # not as root: permissions hold
  expect_rc 1 "${STUDY[@]}" --out r4.h5 --tabular ro/t.csv
  expect_err "--tabular 'ro/t.csv': cannot write in folder 'ro'"
  check "read-only folder: no results file" [ ! -e r4.h5 ] && [ ! -e r4.h5.partial ]
fi
chmod 755 ro

finish test_output_paths
