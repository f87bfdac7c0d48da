# The density ladder (issue 27; docs/decisions/density-ladder.md), included by
# Makefile.experiments after mk/scenes.mk. Part of `all` with the scene experiment
# (DENSITY_LADDER follows SCENE_EXPERIMENT unless given):
#
#   make -f Makefile.experiments density -j2 [DENSITY_LEVELS="10 25 50"] [DENSITY_SEEDS="21 22"]
#
# The scene experiment's tiles (mk/scenes.mk: its recipe, cover levels and models) rendered at
# each of DENSITY_LEVELS nominal points per m², noise 0, each level a `make scenes` of its own
# with the pixel spacing that gives that density:
#   out/density/d<LEVEL>/<cover>/tile-<seed>/...            the scene experiment's layout
#   results/density/d<LEVEL>/score.json (+ CSV tables)      score of the level's tiles
#   out/density/d<LEVEL>/detect-ablation[-K]/..., results/density/d<LEVEL>/detect-ablation[-K]/score.json
#                                                           detect's ablations on the class-level rungs
# The render's seed is the tile's place (scenes/<cover>/<seed>), not its spacing: every level
# shows the same scenes (terrain, trees, vehicles, poses), sampled more or less densely.
# The report's "Density ladder" section reads the levels (the manifest's `density` records),
# each level's measured density (detect's index.json) and the stages' CPU time per hectare.
#
# Spacing: the scene recipe's four looks (two flight lines, two 75° looks each) give
# DENSITY_K / spacing² points per m² of open ground (measured on development tiles:
# docs/decisions/density-ladder.md), so spacing = sqrt(DENSITY_K / LEVEL), in whole mm.
DENSITY_LADDER ?= $(SCENE_EXPERIMENT)
$(if $(filter-out 0 1,$(DENSITY_LADDER)),$(error DENSITY_LADDER=$(DENSITY_LADDER): must be 0 or 1))
DENSITY_LEVELS ?= 10 25 50 100 200 400 800
DENSITY_SEEDS ?= 21 22 23
DENSITY_COVERS ?= light medium dense
DENSITY_K ?= 4.45
# The vehicles drawn (the recipe's random list): the scene experiment's five models by default;
# e.g. procedural family instances (family:<class>:<n>, classify's own classes) to see the
# class level without the five models' shapes (docs/decisions/density-ladder.md).
DENSITY_MODELS ?= $(SCENE_MODELS)
DENSITY_DIR := $(OUT)/density
DENSITY_RES := $(RES)/density
# detect's parameters on the class-level rungs of both ladders (density-ladder.md, "detect's end-gap
# on the class-level rungs", stop 61): the rungs whose nominal density is at most DENSITY_CLASS_MAX
# points (pulses) per m² (50, TILE_MODEL_DENSITY's value from stop 49 to 68: the rungs 10, 25, 50,
# whose candidates were then answered by classify alone but for a few at 50; with the model level
# at 20 since stop 69 some of 25's and 50's run the model chain too). DENSITY_DETECT is given to their `make scenes`
# as SCENE_DETECT; share/params/detect-ladder.ini is `end-gap = 1` (docs/decisions/detect.md §19).
# The higher rungs, the scene experiment and the real tiles keep detect's defaults (end-gap 0:
# detect.md §19's two false alarms on the real development tiles). Empty: detect's defaults.
DENSITY_DETECT ?= share/params/detect-ladder.ini
DENSITY_CLASS_MAX ?= 50
# detect's ablations on the class-level rungs, in the list form of classify's
# (experiment-graph.md §8): the K-th entry, a detect parameter file, is the variant detect-ablation
# (K = 1) or detect-ablation-K, "-" leaves its place empty. A detect ablation changes the
# candidates, so it is the rung's whole chain once more on the rung's renders (detect with the
# entry's file, classify, the model chain where a candidate reaches it, collect, score; no ablation
# of its own):
# a `make scenes` of its own into out/density/<rung>/<variant>/ and
# results/density/<rung>/<variant>/score.json, one density-detect record each (the report's
# "detect's ablation on the density ladder"). The first is detect's default before stop 61
# (end-gap 0). An entry may also be TILE_MODEL_DENSITY=<points/m²>, the model level's ablation:
# the rung's whole chain again with DENSITY_DETECT and the model level (mk/scenes.mk) at that
# density, into the variant model-ablation-K (K its place in the list; the report's "the model
# level's ablation on the density ladder"). The second is the model level before stop 69 (50;
# docs/decisions/density-scale.md, "The model level at 20 points/m², re-measured"): the
# class-level rungs are those whose objects measure 20-64 points/m², where the two levels differ.
# Empty: none.
DENSITY_DETECT_ABLATIONS ?= bench/density/detect-end-gap-0.ini TILE_MODEL_DENSITY=50
DENSITY_SENSOR_DETECT_ABLATIONS ?= $(DENSITY_DETECT_ABLATIONS)
# detect_variant(K, LIST): the ablation at place K of LIST (detect-ablation, detect-ablation-2, ...;
# model-ablation-K for a TILE_MODEL_DENSITY=<value> entry).
detect_variant = $(if $(findstring =,$(word $(1),$(2))),model-ablation-$(1),detect-ablation$(if $(filter-out 1,$(1)),-$(1)))
# density_detect_set(ENTRY): the sub-make's variables of an entry: detect's parameter file, or
# DENSITY_DETECT and the model level.
density_detect_set = $(if $(findstring =,$(1)),SCENE_DETECT=$(DENSITY_DETECT) $(1),SCENE_DETECT=$(1))
# A detect ablation renders nothing: its chain reads the canopy rung's tiles (SCENE_TILE_DIR,
# mk/scenes.mk). The rung's make keeps its renders (SCENE_KEEP_TILE_SCANS=1) and the ablations run
# after it, one after another; the last deletes them. (Until stop 62 each ablation rendered its
# own copy of every tile: 54 renders, ~7 CPU-min of the tree; docs/decisions/cost.md §29.)
# density_detect_keep(LEVEL, CLASS LEVELS, LIST): SCENE_KEEP_TILE_SCANS=1 on a class-level rung
# with detect ablations.
density_detect_keep = $(if $(and $(filter $(1),$(2)),$(call list_places,$(3))), SCENE_KEEP_TILE_SCANS=1)
# density_detect_prev(K, LIST): the place of the detect ablation before place K in LIST (none: empty).
density_detect_prev = $(lastword $(filter $(filter-out $(1),$(wordlist 1,$(1),$(call list_numbers,$(2)))),$(call \
  list_places,$(2))))
# density_detect_tiles(RUNG, K, LIST): the K-th ablation's share of RUNG's renders: read them, and
# keep them unless it is the last ablation.
density_detect_tiles = SCENE_TILE_DIR=$(DENSITY_DIR)/$(1)$(if $(filter-out $(lastword $(call list_places,$(3))),$(2)), \
  SCENE_KEEP_TILE_SCANS=1)
# LEVEL:SPACING_MM:SPACING_M:CLASS per level (CLASS 1 on a class-level rung: LEVEL <=
# DENSITY_CLASS_MAX, below), or ERROR <why>: one shell for the checks (whole levels
# 1-99999, rising: the manifest's order; whole seeds of up to 9 digits; DENSITY_K and
# DENSITY_CLASS_MAX numbers; no {m,n} in the patterns: Debian's mawk has none) and the spacings, and
# only where the ladder is read (every parse pays for its shells: docs/decisions/cost.md).
ifneq ($(filter 1,$(DENSITY_LADDER))$(filter density,$(MAKECMDGOALS)),)
density_pairs := $(shell awk -v k='$(DENSITY_K)' -v levels='$(strip $(DENSITY_LEVELS))' \
  -v seeds='$(strip $(DENSITY_SEEDS))' -v cmax='$(DENSITY_CLASS_MAX)' 'BEGIN { \
  if (k !~ /^[0-9]+(\.[0-9]+)?$$/) { print "ERROR DENSITY_K=" k " must be a number"; exit } \
  if (cmax !~ /^[0-9]+(\.[0-9]+)?$$/) { print "ERROR DENSITY_CLASS_MAX=" cmax " must be a number"; exit } \
  m = split(seeds, s, " "); for (i = 1; i <= m; i++) if (s[i] !~ /^[0-9]+$$/ || length(s[i]) > 9) { \
    print "ERROR DENSITY_SEEDS: " s[i] " is not a whole number"; exit } \
  n = split(levels, d, " "); for (i = 1; i <= n; i++) { \
    if (d[i] !~ /^[1-9][0-9]*$$/ || length(d[i]) > 5) { print "ERROR DENSITY_LEVELS: " d[i] " is not a whole number of points/m² from 1 to 99999"; exit } \
    if (i > 1 && d[i] + 0 <= d[i - 1] + 0) { print "ERROR DENSITY_LEVELS=" levels ": the levels must rise"; exit } \
    mm = int(1000 * sqrt(k / d[i]) + 0.5); out = out sprintf("%s:%d:%.3f:%d ", d[i], mm, mm / 1000, d[i] + 0 <= cmax + 0) } \
  print out }')
$(if $(filter ERROR,$(firstword $(density_pairs))),$(error $(wordlist 2,$(words $(density_pairs)),$(density_pairs))))
$(foreach f,$(filter-out - $(classify_sim_files),$(DENSITY_CLASSIFY_ABLATIONS)),$(if $(wildcard $(f)),,$(error \
  DENSITY_CLASSIFY_ABLATIONS: $(f) does not exist)))
$(foreach f,$(DENSITY_DETECT) $(call ablation_files,$(DENSITY_DETECT_ABLATIONS)),$(if $(wildcard $(f)),,$(error \
  DENSITY_DETECT or DENSITY_DETECT_ABLATIONS: $(f) does not exist)))
$(call model_entries_check,$(DENSITY_DETECT_ABLATIONS),DENSITY_DETECT_ABLATIONS)
endif
# The ladder on the realistic sensor (docs/decisions/density-ladder.md, "The ladder on the
# realistic sensor"): the same tiles rendered in sensor mode (mk/scenes.mk SCENE_SENSOR) with
# the preset DENSITY_SENSOR at each of DENSITY_SENSOR_LEVELS nominal pulses/m²:
#   out/density/<preset>-<LEVEL>/..., results/density/<preset>-<LEVEL>/score.json
# The density is set by the preset's pulse_rate × f and speed / f, f = sqrt(LEVEL /
# DENSITY_SENSOR_L0) (across- and along-track spacing both shrink by f), DENSITY_SENSOR_L0 the
# pulses/m² the preset gives on the ladder's tile with its own keys (rangetrace's truth.json
# density.pulses_per_m2, measured on development seeds 101-103: 26.5 for als_qL1). Empty
# DENSITY_SENSOR: no sensor ladder.
DENSITY_SENSOR ?= als_qL1
DENSITY_SENSOR_LEVELS ?= 10 25 50
DENSITY_SENSOR_L0 ?= 26.5
# classify's ablations on every level of the pixel ladder (SCENE_CLASSIFY_ABLATIONS of its `make
# scenes`: the K-th entry is the variant class-ablation (K = 1) or class-ablation-K, "-" leaves its
# place empty). The first is the rung's own (the manifest's density record; the report's
# "classify's ablation on the density ladder"), each later one a density-classify record (the
# report's "classify's second ablation ...", third, ...). Each is classify-sim.ini with one
# default before its change: the roughness threshold's floor (0.1 m, before classify.md §28), the
# shoulder gate off (min-shoulder 0, before §30), the oval-outline gate's step over every profile
# bin (rectangularity-sampled false, before §37), no open-top gate (max-rim 0, before §38), no
# pickup bed cue (min-bed 0, before §39). Empty: none.
# The five files (and the sensor ladder's echo-late-0, below) are written by make (Makefile.experiments CLASSIFY_SIM_VARIANTS).
DENSITY_CLASSIFY_ABLATIONS ?= $(foreach n,floor-100 shoulder-0 sampled-0 rim-0 bed-0,$(call classify_sim_variant,$(n)))
# The same on every sensor level: its first is classify-sim.ini before classify.md §23
# (max-late-returns 0.35; the sensor tiles are the only ones with return numbers), then by
# default the pixel ladder's others, then late returns not waived for hard objects (echo-late
# false, before §44; the sensor tiles are the only ones with echo widths, so not on the pixel ladder).
DENSITY_SENSOR_CLASSIFY_ABLATIONS ?= bench/density/classify-sim-late-0.35.ini $(wordlist 2,$(words \
  $(DENSITY_CLASSIFY_ABLATIONS)),$(DENSITY_CLASSIFY_ABLATIONS)) $(call classify_sim_variant,echo-late-0)
# verify's ablation on every level of both ladders (SCENE_VERIFY_ABLATION of its `make scenes`: the
# model-level candidates verified a second time with these options, collected and scored as
# <level>/verify-ablation/score.json; the report's "verify's ablation on the density ladder"):
# --seen-spacing=0, the free-space test before docs/decisions/verify.md §17 (the seen radius
# inlier-radius alone, not the candidate's own sample spacing). Options as --name=value; empty:
# none.
DENSITY_VERIFY_ABLATION ?= --seen-spacing=0
$(call verify_options_check,DENSITY_VERIFY_ABLATION)
density_verify_change = $(subst $(space),+,$(strip $(DENSITY_VERIFY_ABLATION)))
# LEVEL:PULSE_RATE:SPEED:CLASS per level, or ERROR <why> (the preset's keys read from its file;
# CLASS as the pixel ladder's).
ifneq ($(DENSITY_SENSOR),)
ifneq ($(filter 1,$(DENSITY_LADDER))$(filter density density-sensor,$(MAKECMDGOALS)),)
$(if $(filter 1,$(words $(DENSITY_SENSOR))),,$(error DENSITY_SENSOR=$(DENSITY_SENSOR) must name one preset of share/sensors/))
$(if $(wildcard share/sensors/$(DENSITY_SENSOR).ini),,$(error DENSITY_SENSOR=$(DENSITY_SENSOR): no share/sensors/$(DENSITY_SENSOR).ini))
$(foreach f,$(filter-out - $(classify_sim_files),$(DENSITY_SENSOR_CLASSIFY_ABLATIONS)),$(if $(wildcard $(f)),,$(error \
  DENSITY_SENSOR_CLASSIFY_ABLATIONS: $(f) does not exist)))
$(foreach f,$(call ablation_files,$(DENSITY_SENSOR_DETECT_ABLATIONS)),$(if $(wildcard $(f)),,$(error \
  DENSITY_SENSOR_DETECT_ABLATIONS: $(f) does not exist)))
$(call model_entries_check,$(DENSITY_SENSOR_DETECT_ABLATIONS),DENSITY_SENSOR_DETECT_ABLATIONS)
density_sensor_keys := $(shell awk -v l0='$(DENSITY_SENSOR_L0)' -v levels='$(strip $(DENSITY_SENSOR_LEVELS))' -v cmax='$(DENSITY_CLASS_MAX)' \
  -v f='share/sensors/$(DENSITY_SENSOR).ini' 'BEGIN { \
  if (l0 !~ /^[0-9]+(\.[0-9]+)?$$/ || l0 + 0 <= 0) { print "ERROR DENSITY_SENSOR_L0=" l0 " must be a positive number"; exit } \
  if (cmax !~ /^[0-9]+(\.[0-9]+)?$$/) { print "ERROR DENSITY_CLASS_MAX=" cmax " must be a number"; exit } \
  while ((getline line < f) > 0) { sub(/#.*/, "", line); gsub(/[ \t]/, "", line); \
    if (line ~ /^pulse_rate=/) pr = substr(line, 12) + 0; if (line ~ /^speed=/) sp = substr(line, 7) + 0 } \
  if (!(pr > 0) || !(sp > 0)) { print "ERROR " f " gives no pulse_rate and speed"; exit } \
  n = split(levels, d, " "); for (i = 1; i <= n; i++) { \
    if (d[i] !~ /^[1-9][0-9]*$$/ || length(d[i]) > 5) { print "ERROR DENSITY_SENSOR_LEVELS: " d[i] " is not a whole number of pulses/m² from 1 to 99999"; exit } \
    if (i > 1 && d[i] + 0 <= d[i - 1] + 0) { print "ERROR DENSITY_SENSOR_LEVELS=" levels ": the levels must rise"; exit } \
    g = sqrt(d[i] / l0); r = int(pr * g + 0.5); v = sprintf("%.2f", sp / g); \
    if (r < 1000 || r > 5000000 || v + 0 < 1 || v + 0 > 150) { print "ERROR DENSITY_SENSOR_LEVELS: " d[i] " needs pulse_rate " r \
      " and speed " v ", beyond the sensor keys bounds (share/sensors/README.md)"; exit } \
    out = out sprintf("%s:%d:%s:%d ", d[i], r, v, d[i] + 0 <= cmax + 0) } print out }')
$(if $(filter ERROR,$(firstword $(density_sensor_keys))),$(error $(wordlist 2,$(words $(density_sensor_keys)),$(density_sensor_keys))))
endif
endif
density_sensor_rate = $(word 2,$(subst :, ,$(filter $(1):%,$(density_sensor_keys))))
density_sensor_speed = $(word 3,$(subst :, ,$(filter $(1):%,$(density_sensor_keys))))
DENSITY_SENSOR_SCORES := $(if $(DENSITY_SENSOR),$(foreach d,$(DENSITY_SENSOR_LEVELS),$(DENSITY_RES)/$(DENSITY_SENSOR)-$(d)/score.json))
density_mm = $(word 2,$(subst :, ,$(filter $(1):%,$(density_pairs))))
density_m = $(word 3,$(subst :, ,$(filter $(1):%,$(density_pairs))))
DENSITY_SCORES := $(foreach d,$(DENSITY_LEVELS),$(DENSITY_RES)/d$(d)/score.json)
# The class-level rungs of each ladder (DENSITY_CLASS_MAX) and their detect ablations' scores.
density_class_levels := $(foreach p,$(density_pairs),$(if $(filter 1,$(word 4,$(subst :, ,$(p)))),$(firstword $(subst :, ,$(p)))))
density_sensor_class_levels := $(foreach p,$(density_sensor_keys),$(if $(filter 1,$(word 4,$(subst :, ,$(p)))),$(firstword \
  $(subst :, ,$(p)))))
DENSITY_DETECT_SCORES := $(foreach d,$(density_class_levels),$(foreach k,$(call list_places,$(DENSITY_DETECT_ABLATIONS)),$(DENSITY_RES)/d$(d)/$(call \
  detect_variant,$(k),$(DENSITY_DETECT_ABLATIONS))/score.json))
DENSITY_SENSOR_DETECT_SCORES := $(if $(DENSITY_SENSOR),$(foreach d,$(density_sensor_class_levels),$(foreach k,$(call \
  list_places,$(DENSITY_SENSOR_DETECT_ABLATIONS)),$(DENSITY_RES)/$(DENSITY_SENSOR)-$(d)/$(call detect_variant,$(k),$(DENSITY_SENSOR_DETECT_ABLATIONS))/score.json)))

# The records of the experiment's manifest (Makefile.experiments): level, spacing (m), score;
# the sensor ladder's: level, preset, score [, classify's ablation: its parameter file and score];
# after each level, verify's ablation: the ladder (pixel or the preset), level, options, score.
density_verify_record = $(if $(DENSITY_VERIFY_ABLATION),$(call ml,density-verify $(1) $(2) $(density_verify_change) \
  $(DENSITY_RES)/$(3)/verify-ablation/score.json))
# density_first(LIST, RUNG): the rung's own classify ablation, LIST's first entry (the density or
# density-sensor record's last two words: its parameter file and score), none for "-".
density_first = $(if $(filter-out -,$(firstword $(1))), $(firstword $(1)) $(DENSITY_RES)/$(2)/class-ablation/score.json)
# density_classify_records(LADDER, LEVEL, RUNG, LIST): LIST's later entries, classify's second,
# third, ... ablation on a rung, one density-classify record each.
density_classify_records = $(foreach k,$(filter-out 1,$(call list_places,$(4))),$(call ml,density-classify $(1) $(2) \
  $(word $(k),$(4)) $(DENSITY_RES)/$(3)/$(call class_variant,$(k))/score.json))
# density_detect_records(LADDER, LEVEL, RUNG, LIST): on a class-level rung, detect's ablations
# (LIST's entries), one density-detect record each.
density_detect_records = $(if $(filter $(2),$(if $(filter pixel,$(1)),$(density_class_levels),$(density_sensor_class_levels))),$(foreach \
  k,$(call list_places,$(4)),$(call ml,density-detect $(1) $(2) $(word $(k),$(4)) $(DENSITY_RES)/$(3)/$(call \
  detect_variant,$(k),$(4))/score.json)))
EXPERIMENT_DENSITY := $(if $(filter 1,$(DENSITY_LADDER)),$(foreach d,$(DENSITY_LEVELS),$(call ml,density $(d) \
  $(call density_m,$(d)) $(DENSITY_RES)/d$(d)/score.json$(call density_first,$(DENSITY_CLASSIFY_ABLATIONS),d$(d)))$(call \
  density_verify_record,pixel,$(d),d$(d))$(call density_classify_records,pixel,$(d),d$(d),$(DENSITY_CLASSIFY_ABLATIONS))$(call \
  density_detect_records,pixel,$(d),d$(d),$(DENSITY_DETECT_ABLATIONS)))$(if \
  $(DENSITY_SENSOR),$(foreach d,$(DENSITY_SENSOR_LEVELS),$(call \
  ml,density-sensor $(d) $(DENSITY_SENSOR) $(DENSITY_RES)/$(DENSITY_SENSOR)-$(d)/score.json$(call \
  density_first,$(DENSITY_SENSOR_CLASSIFY_ABLATIONS),$(DENSITY_SENSOR)-$(d)))$(call \
  density_verify_record,$(DENSITY_SENSOR),$(d),$(DENSITY_SENSOR)-$(d))$(call \
  density_classify_records,$(DENSITY_SENSOR),$(d),$(DENSITY_SENSOR)-$(d),$(DENSITY_SENSOR_CLASSIFY_ABLATIONS))$(call \
  density_detect_records,$(DENSITY_SENSOR),$(d),$(DENSITY_SENSOR)-$(d),$(DENSITY_SENSOR_DETECT_ABLATIONS)))))

ifeq ($(filter scenes,$(MAKECMDGOALS)),)
# density_args(LEVEL): the level's `make scenes`: its own directories and spacing, noise 0, the
# scores only (no pictures, no PCL baseline, no size-only nor collect ablation), verify's
# ablation and, on the pixel ladder, classify's.
# density_args(LEVEL[, RUNG, RENDER]): the same for rung RUNG (default d<LEVEL>) rendered with the
# scene variables RENDER (default the level's spacing): the sensor ladder's levels.
# density_base(LEVEL, RUNG, RENDER): the `make scenes` of rung RUNG (default d<LEVEL>; its
# directories out/density/RUNG, results/density/RUNG) rendered with the scene variables RENDER
# (default the level's spacing), noise 0, the scores only, no ablation.
density_base = --no-print-directory -f $(firstword $(MAKEFILE_LIST)) scenes PROGRESS=0 \
  SCENE_DIR=$(DENSITY_DIR)/$(or $(2),d$(1)) SCENE_RES=$(DENSITY_RES)/$(or $(2),d$(1)) \
  $(or $(3),SCENE_SPACING=$(call density_mm,$(1))mm) \
  SCENE_SEEDS="$(DENSITY_SEEDS)" SCENE_COVERS="$(DENSITY_COVERS)" SCENE_MODELS=$(DENSITY_MODELS) SCENE_NOISES=0 SCENE_BASELINE= \
  SCENE_SIZE_ONLY=0 SCENE_PICTURES=0 SCENE_COLLECT_ABLATION=
# density_detect_arg(LEVEL, CLASS LEVELS, FILE): detect's parameters FILE on a class-level rung.
density_detect_arg = $(if $(filter $(1),$(2)), SCENE_DETECT=$(3))
density_args = $(call density_base,$(1),$(2),$(3))$(if $(2),,$(call density_detect_arg,$(1),$(density_class_levels),$(DENSITY_DETECT))$(call \
  density_detect_keep,$(1),$(density_class_levels),$(DENSITY_DETECT_ABLATIONS)))$(if \
  $(DENSITY_VERIFY_ABLATION), SCENE_VERIFY_ABLATION='$(DENSITY_VERIFY_ABLATION)')$(if \
  $(2),,$(call density_class_arg,$(DENSITY_CLASSIFY_ABLATIONS)))
# density_class_arg(LIST): a level's classify ablations (none: no argument).
density_class_arg = $(if $(strip $(1)), SCENE_CLASSIFY_ABLATIONS='$(strip $(1))')
# density_sensor_args(LEVEL): a level of the sensor ladder.
density_sensor_render = SCENE_SENSOR=$(DENSITY_SENSOR) \
  SCENE_SENSOR_KEYS="pulse_rate=$(call density_sensor_rate,$(1)) speed=$(call density_sensor_speed,$(1))"
density_sensor_args = $(call density_args,$(1),$(DENSITY_SENSOR)-$(1),$(call density_sensor_render,$(1)) \
  $(call density_class_arg,$(DENSITY_SENSOR_CLASSIFY_ABLATIONS))$(call \
  density_detect_arg,$(1),$(density_sensor_class_levels),$(DENSITY_DETECT))$(call \
  density_detect_keep,$(1),$(density_sensor_class_levels),$(DENSITY_SENSOR_DETECT_ABLATIONS)))
# density_detect_args(LEVEL, K) and density_sensor_detect_args(LEVEL, K): detect's K-th ablation
# on a class-level rung of either ladder (DENSITY_[SENSOR_]DETECT_ABLATIONS).
density_detect_args = $(call density_base,$(1),d$(1)/$(call detect_variant,$(2),$(DENSITY_DETECT_ABLATIONS))) $(call \
  density_detect_set,$(word $(2),$(DENSITY_DETECT_ABLATIONS))) $(call density_detect_tiles,d$(1),$(2),$(DENSITY_DETECT_ABLATIONS))
density_sensor_detect_args = $(call density_base,$(1),$(DENSITY_SENSOR)-$(1)/$(call detect_variant,$(2),$(DENSITY_SENSOR_DETECT_ABLATIONS)),$(call \
  density_sensor_render,$(1))) $(call density_detect_set,$(word $(2),$(DENSITY_SENSOR_DETECT_ABLATIONS))) $(call \
  density_detect_tiles,$(DENSITY_SENSOR)-$(1),$(2),$(DENSITY_SENSOR_DETECT_ABLATIONS))
# As for the scene experiment: under -q each level's sub-make is asked (`make -q`, which renders
# nothing), only when the ladder is on (the question builds the tools it needs, and a make
# without the ladder must not); otherwise the step always runs and make compares score.json's
# time afterwards.
ifneq ($(findstring q,$(make_letters))$(DENSITY_LADDER),q1)
density_force = FORCE
else
density_force = $(if $(shell $(MAKE) -q $(MAKEOVERRIDES) $(or $(2),$(call density_args,$(1))) >/dev/null 2>&1 || echo stale),FORCE)
endif
DENSITY_TOOLS := rangetrace addnoise detect classify fitvox cocone ncut gmatch verify collect score topview
define density_rule
$(DENSITY_RES)/d$(1)/score.json: $(call density_force,$(1)) $(foreach t,$(DENSITY_TOOLS),$(call tool,$(t))) \
    $(MODELBASE) $(VERIFY_SURFACES)
	+@$(MAKE) $(call density_args,$(1))
endef
$(foreach d,$(DENSITY_LEVELS),$(eval $(call density_rule,$(d))))
define density_sensor_rule
$(DENSITY_RES)/$(DENSITY_SENSOR)-$(1)/score.json: $(call density_force,$(1),$(call density_sensor_args,$(1))) \
    $(foreach t,$(DENSITY_TOOLS),$(call tool,$(t))) $(MODELBASE) $(VERIFY_SURFACES)
	+@$(MAKE) $(call density_sensor_args,$(1))
endef
$(if $(DENSITY_SENSOR),$(foreach d,$(DENSITY_SENSOR_LEVELS),$(eval $(call density_sensor_rule,$(d)))))
# density_detect_rule(LADDER RUNG, LEVEL, K, ARGS, LIST): detect's K-th ablation on a class-level
# rung, after the rung itself and the ablation before it (density_detect_tiles: they share its renders).
define density_detect_rule
$(DENSITY_RES)/$(1)/$(call detect_variant,$(3),$(5))/score.json: $(call density_force,$(2),$(4)) \
    $(foreach t,$(DENSITY_TOOLS),$(call tool,$(t))) $(MODELBASE) $(VERIFY_SURFACES) $(DENSITY_RES)/$(1)/score.json$(foreach \
    p,$(call density_detect_prev,$(3),$(5)), $(DENSITY_RES)/$(1)/$(call detect_variant,$(p),$(5))/score.json)
	+@$(MAKE) $(4)
endef
$(foreach d,$(density_class_levels),$(foreach k,$(call list_places,$(DENSITY_DETECT_ABLATIONS)),$(eval $(call \
  density_detect_rule,d$(d),$(d),$(k),$(call density_detect_args,$(d),$(k)),$(DENSITY_DETECT_ABLATIONS)))))
$(if $(DENSITY_SENSOR),$(foreach d,$(density_sensor_class_levels),$(foreach k,$(call list_places,$(DENSITY_SENSOR_DETECT_ABLATIONS)),$(eval \
  $(call density_detect_rule,$(DENSITY_SENSOR)-$(d),$(d),$(k),$(call density_sensor_detect_args,$(d),$(k)),$(DENSITY_SENSOR_DETECT_ABLATIONS))))))
.PHONY: density density-sensor
density: $(DENSITY_SCORES) $(DENSITY_SENSOR_SCORES) $(DENSITY_DETECT_SCORES) $(DENSITY_SENSOR_DETECT_SCORES)
density-sensor: $(DENSITY_SENSOR_SCORES) $(DENSITY_SENSOR_DETECT_SCORES)
ifeq ($(DENSITY_LADDER),1)
$(RES)/report.md: $(DENSITY_SCORES) $(DENSITY_SENSOR_SCORES) $(DENSITY_DETECT_SCORES) $(DENSITY_SENSOR_DETECT_SCORES)
# The report writes the ladder's tables (ladder.csv, ladder-rates.csv, ladder-errors.csv); the
# pictures draw two of them, one panel per metric, one line per cover level.
$(DENSITY_RES)/ladder-rates.png: $(RES)/report.md $(call tool,figures)
	@$(STAGE) $@ -- $(XRUN) $(BIN)/figures plot -i $(DENSITY_RES)/ladder-rates.csv --x level --y value --lo lo --hi hi \
	  --series cover --panel metric --xlabel "nominal density (points/m²)" --ylabel "rate" --title "ladder" -o $@
$(DENSITY_RES)/ladder-errors.png: $(RES)/report.md $(call tool,figures)
	@$(STAGE) $@ -- $(XRUN) $(BIN)/figures plot -i $(DENSITY_RES)/ladder-errors.csv --x level --y value --lo lo --hi hi \
	  --series cover --panel metric --xlabel "nominal density (points/m²)" --ylabel "deg or per ha" --title "ladder" -o $@
all: $(DENSITY_RES)/ladder-rates.png $(DENSITY_RES)/ladder-errors.png
endif
endif
