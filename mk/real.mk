# Real airborne tiles (issue 26; docs/decisions/real-tiles.md "The experiment"), included by
# Makefile.experiments after mk/scenes.mk. Part of `all` (REAL_TILES=1, the default):
#
#   make -f Makefile.experiments real-tiles -j2 [REAL_DATA=../shared/data/real] [REAL_TIMEOUT=180]
#
# runs the `tile` workflow (mk/scenes.mk: `make tile TILE=… MODELBASE=… OUT=…`, unchanged) on
# each committed real tile of share/real/ (its README: sources, licences) with the modelbase the
# experiment builds (out/modelbase, as the scene experiment), into
#   out/real/<tile>/{detections.json, detections.geojson, cands/, classes.ply, top.png, …}
#   out/real/<tile>/score.json     the urban tiles: `score` against share/real/<tile>.truth.json
#   out/real/<tile>/tile.time      the tile's whole run: wall s, peak KiB, user and system CPU s
#                                  of the sub-make and every stage under it (GNU time, the
#                                  format of the stages' .time files, tools/stagerun)
# and the report's "Real tiles" section reads them (the experiment manifest's `real` records).
#
# Tiles: urban tiles with hand labels and forest plots without vehicles (forest_lareunion, 0.25 ha,
# and since stop 66 23 more, 6.36 ha: every vehicle answer there is a false alarm). REAL_DATA=<dir>
# (default: none) adds the GPL-3 forest plot forest_bcts_1 (≈ 5 ha, not committed) from
# <dir>/forest_bcts_1.laz or <dir>/laz/forest_bcts_1.laz.
#
# The tiles run one after another (an order-only chain), each sub-make with make's job slots
# for its candidates, so a tile's wall time is its own. Each is time-boxed: a tile whose
# workflow has not finished after REAL_TIMEOUT seconds is stopped (timeout kills its process
# group), recorded as not finished (tile.time kept, its detections and score removed) and the
# experiment goes on; the report says so. A tile on which a tool of the workflow fails by its
# own error (the sub-make exits 2: e.g. detect refusing a closed-canopy plot where it finds too
# little ground) is recorded the same way, as failed: on real data a refusal is a result, and the
# report quotes the tool's error from the tile's logs. A sub-make killed otherwise (a signal)
# fails make. A tile re-runs when the tile, the modelbase, a tool of the workflow
# or a stage's parameters change, and then from scratch (its directory removed first), so
# tile.time is always a whole run's: the report's "Time per tile" measures the issue's 60 s
# target (until stop 66 the sub-make redid only what was out of date, and after an incremental
# `all` the report showed a fraction of a second; a whole chain of real tiles is ≈ 1 CPU-min).
#
# classify's parameters: REAL_CLASSIFY (default share/params/classify.ini, the thresholds fitted
# on the real development tiles ahn3_delft_1 and forest_bcts_1; docs/decisions/classify.md §5).
# The ablation `make -f Makefile.experiments real-tiles-sim -j2` runs the same tiles with the
# thresholds fitted on simulated tiles (REAL_CLASSIFY_SIM, default share/params/classify-sim.ini)
# into $(OUT)/real-sim/<tile>/ (same files, same time box); REAL_ABLATION=1 makes `all` run it too.
#
# classify's ablations (a changed default keeps its ablation in the report): REAL_CLASSIFY_ABLATIONS=
# <ini> ... runs every tile's workflow again with each of those classify parameters, the K-th
# into $(OUT)/real-ablation/<tile>/ (K = 1) or $(OUT)/real-ablation-K/<tile>/ (same files, same
# time box; after canopy's tiles and the ablations before it, one tile at a time; "-" leaves its
# place empty), part of `all` with the real tiles, and the report's "Real tiles" shows each
# beside canopy's. Default: classify.ini without the gap bridge and its fill
# ($(OUT)/params/classify-bridge-0.ini: bridge = 0, bridge-fill = 0, bridge-min-share = 0, the
# options' own defaults, written as classify echoes them; classify.md §21, §27), then with
# unmeasured filled where the crop has no open ground ($(OUT)/params/classify-tile-ground-0.ini:
# fill-tile-ground = false, §31), then with the tile's first returns not standing in for its
# open ground ($(OUT)/params/classify-tile-first-0.ini: fill-tile-first = false, §46). Each changed
# default of classify.ini has its own (until stop 59 the first turned off both). An entry may also
# be TILE_MODEL_DENSITY=<points/m²>, the model level's ablation: classify.ini (REAL_CLASSIFY) and
# the tile workflow's model level at that density (mk/scenes.mk), into $(OUT)/real-ablation-K/
# alike (the report's "The model level's ablation on the real tiles"). The fourth is the model
# level before stop 69 (50; docs/decisions/density-scale.md, "The model level at 20 points/m²,
# re-measured"). Empty: none.
# REAL_CLASSIFY_ABLATION, REAL_CLASSIFY_ABLATION_2, ..., when set (the command lines of
# tests/pipeline/progress_count.sh and the decision records), set the list's first, second, ...
# place (empty: none there).
#
# The three default files are written by make, as classify-sim.ini's (Makefile.experiments
# CLASSIFY_SIM_VARIANTS, ini_variants): REAL_CLASSIFY_VARIANTS NAME:KEY:VALUE[:KEY:VALUE...] is
# $(OUT)/params/classify-NAME.ini (real_classify_variant(NAME)), $(P)/classify.ini with those keys
# set, at parse time when their text changes, by every make of the experiment's goals
# (docs/decisions/experiment-graph.md §12; until stop 62 committed copies in share/real/).
REAL_TILES ?= 1
REAL_CLASSIFY_VARIANTS := bridge-0:bridge:0:bridge-fill:0:bridge-min-share:0 \
  tile-ground-0:fill-tile-ground:false tile-first-0:fill-tile-first:false
real_classify_variant = $(OUT)/params/classify-$(1).ini
# (the three files: the list's existence check leaves them out, make writes them)
real_classify_files = $(call ini_variant_files,real_classify_variant,$(REAL_CLASSIFY_VARIANTS))
ifneq ($(and $(opts_thesis),$(wildcard $(P)/classify.ini)),)
$(call ini_variants,$(P)/classify.ini,real_classify_variant,$(REAL_CLASSIFY_VARIANTS))
endif
REAL_CLASSIFY_ABLATIONS ?= $(call real_classify_variant,bridge-0) $(call real_classify_variant,tile-ground-0) \
  $(call real_classify_variant,tile-first-0) TILE_MODEL_DENSITY=50
# real_named(K): the name of place K (REAL_CLASSIFY_ABLATION, REAL_CLASSIFY_ABLATION_2, ...);
# real_abl_list: the list with each place so named and set taken from it ("-" when empty).
real_named = REAL_CLASSIFY_ABLATION$(if $(filter-out 1,$(1)),_$(1))
real_abl_list := $(foreach k,$(call list_numbers,$(REAL_CLASSIFY_ABLATIONS)),$(if $(filter-out \
  undefined,$(origin $(call real_named,$(k)))),$(or $($(call real_named,$(k))),-),$(word $(k),$(REAL_CLASSIFY_ABLATIONS))))
# real_variant(K): the ablation at place K (real-ablation, real-ablation-2, ...: its directory
# under $(OUT) and its options kind); real_abl_entry(K): the list's entry; real_abl_ini(K): its
# classify parameters; real_abl_density(K): its model level (TILE_MODEL_DENSITY's, or the entry's
# TILE_MODEL_DENSITY=<value>).
real_variant = real-ablation$(if $(filter-out 1,$(1)),-$(1))
real_abl_entry = $(word $(1),$(real_abl_list))
real_abl_ini = $(if $(findstring =,$(call real_abl_entry,$(1))),$(REAL_CLASSIFY),$(call real_abl_entry,$(1)))
real_abl_density = $(if $(findstring =,$(call real_abl_entry,$(1))),$(patsubst TILE_MODEL_DENSITY=%,%,$(call \
  real_abl_entry,$(1))),$(TILE_MODEL_DENSITY))
REAL_ABL_PLACES := $(call list_places,$(real_abl_list))
REAL_ABLATION ?= 0
$(if $(filter-out 0 1,$(REAL_ABLATION)),$(error REAL_ABLATION=$(REAL_ABLATION): must be 0 or 1))
REAL_CLASSIFY ?= $(P)/classify.ini
REAL_CLASSIFY_SIM ?= $(P)/classify-sim.ini
$(call model_entries_check,$(real_abl_list),REAL_CLASSIFY_ABLATIONS)
$(foreach f,$(REAL_CLASSIFY) $(REAL_CLASSIFY_SIM) $(call ablation_files,$(filter-out $(real_classify_files),$(real_abl_list))),$(if \
  $(wildcard $(f)),,$(error REAL_CLASSIFY: $(f) does not exist)))
$(if $(filter-out 0 1,$(REAL_TILES)),$(error REAL_TILES=$(REAL_TILES): must be 0 or 1))
REAL_URBAN ?= ign_lidarhd_870000_6618000 ahn3_delft_2 ign_stbarth_100m
# The plots without vehicles: forest_lareunion, then (stop 66; real-tiles.md "More forest plots for
# the false-alarm target") an IGN LiDAR HD plot at 92 points/m² and 22 NEON plots at 4-8.
REAL_FOREST ?= forest_lareunion forest_ign_loiret_crop2 forest_neon_osbs_003 forest_neon_osbs_006 \
  $(foreach n,043 044 045 046 047 048 049 050 051 052 053 054 055 056 057 058 059 060 061 062,forest_neon_teak_$(n))
REAL_DATA ?=
REAL_DATA_FOREST ?= forest_bcts_1
# ahn3_delft_1 (3.5 MB, over the repository's 2 MiB file bound) is labelled in share/real but
# its tile is not committed: it runs, and is scored, with REAL_DATA=<dir>.
REAL_DATA_URBAN ?= ahn3_delft_1
REAL_TIMEOUT ?= 180
$(if $(shell printf '%s' '$(REAL_TIMEOUT)' | grep -xE '[1-9][0-9]{0,5}'),,$(error REAL_TIMEOUT=$(REAL_TIMEOUT): \
  whole seconds, 1 or more))
REAL_SHARE := share/real
REAL_OUT := $(OUT)/real
REAL_SIM_OUT := $(OUT)/real-sim

# real_file(name): the tile's file; the REAL_DATA plots from that directory (or its laz/).
real_file = $(if $(filter $(1),$(REAL_URBAN) $(REAL_FOREST)),$(REAL_SHARE)/$(1).laz,$(firstword \
  $(wildcard $(REAL_DATA)/$(1).laz $(REAL_DATA)/laz/$(1).laz) $(REAL_DATA)/$(1).laz))
REAL_EXTRA := $(if $(strip $(REAL_DATA)),$(REAL_DATA_FOREST) $(REAL_DATA_URBAN))
$(foreach t,$(REAL_EXTRA),$(if $(wildcard $(call real_file,$(t))),,$(error \
  REAL_DATA=$(REAL_DATA): no $(t).laz there nor in its laz/)))
# The forest plots first, then the urban tiles by points.
REAL_NAMES := $(REAL_FOREST) $(REAL_URBAN) $(REAL_EXTRA)

# What a tile's run depends on: the tools of the workflow (built here first, so the tiles'
# sub-makes never build one at the same time), classify's stamp once it is built (the class
# level, when the workflow runs it), the stages' parameters and the experiment's modelbase.
REAL_TOOLS := detect fitvox cocone ncut gmatch verify collect score topview
REAL_DEPS = $(foreach t,$(REAL_TOOLS),$(call tool,$(t))) $(wildcard $(STAMPS)/classify.sha) \
  $(wildcard $(P)/*.ini) $(MODELBASE) $(VERIFY_SURFACES)

# The sub-make is a recursive step (`+`, with make's job slots) only in a real run: under -n it
# is printed and under -q the run is reported out of date, never started (REAL_SUBMAKE hides the
# recursion from make's scan of the recipe text).
REAL_SUBMAKE = $(MAKE)
real_plus := $(if $(dry_run),,+)

# real_args(name, out, classify.ini, model level): the arguments of a tile's sub-make.
real_args = --no-print-directory -f $(firstword $(MAKEFILE_LIST)) tile TILE=$(call real_file,$(1)) \
  MODELBASE=$(OUT)/modelbase OUT=$(2)/$(1) TILE_CLASSIFY=$(3) TILE_MODEL_DENSITY=$(4) PROGRESS=0 SCENE_EXPERIMENT=0 \
  FAMILIES=0 REAL_TILES=0
# real_progress(MODE, name, out, classify.ini, model level): the progress count (scripts/progress.sh, state
# $$CANOPY_PROGRESS) takes in (add) the stages a dry run of the tile's sub-make shows, or takes
# them back (drop) when the sub-make stopped early and they will not run (but for those that ran
# since the start, failing: $(OUT)/.progress-<real|real-sim>-<name> marks it); the parent's dry run
# prints the sub-make without running it, so they are not in its plan (issue 31: the tiles'
# stages ran uncounted, then a tile stopped by its time box left its candidates counted). drop
# also takes back the score, which the parent's plan counts.
real_progress = { [ -z "$$$$CANOPY_PROGRESS" ] || { CANOPY_PLANNING=1 $$(REAL_SUBMAKE) -n $(call real_args,$(2),$(3),$(4),$(5)) \
  2>/dev/null; $(if $(and $(filter drop,$(1)),$(wildcard $(REAL_SHARE)/$(2).truth.json)),echo \
  "$(BIN)/stagerun $(3)/$(2)/score.json -- $(BIN)/score";) } | scripts/progress.sh $(1) "$$$$CANOPY_PROGRESS" \
  "$$$$CANOPY_PROGRESS-$(notdir $(3))-$(2)" >/dev/null; }

# The options a tile's run depends on (the options files, Makefile.experiments): the time box,
# classify's parameters and the tile workflow's options as its sub-make reads them (the same
# defaults, but COLLECT_CALIBRATION: the workflow's own default is none, so only a value given on
# the command line or in the environment reaches it). The sub-make then re-runs what they change.
real_calibration = $(if $(filter command% environment%,$(origin COLLECT_CALIBRATION)),$(COLLECT_CALIBRATION))
opts_text_real_tile = $(call real_tile_opts,$(TILE_MODEL_DENSITY))
real_tile_opts = $(call opts_line,timeout,$(REAL_TIMEOUT))$(call opts_line,model-density,$(1))$(call \
  opts_line,density-scale,$(TILE_DENSITY_SCALE))$(call opts_line,raster,$(TOP_RASTER))$(call \
  opts_line,fitvox,$(TILE_FITVOX))$(call opts_line,parameters,$(P))$(call opts_line,model-classes,$(MODEL_CLASSES))$(call \
  opts_line,crs,$(CRS))$(call opts_line,calibration,$(real_calibration))
opts_text_real = $(call opts_line,classify,$(REAL_CLASSIFY))$(opts_text_real_tile)
opts_text_real-sim = $(call opts_line,classify,$(REAL_CLASSIFY_SIM))$(opts_text_real_tile)
$(foreach k,$(REAL_ABL_PLACES),$(eval opts_text_$(call real_variant,$(k)) = $$(call \
  opts_line,classify,$(call real_abl_ini,$(k)))$$(call real_tile_opts,$(call real_abl_density,$(k)))))
# Written only by a make that can run the real tiles, never by the sub-makes of `all`
# (sub_make_goals, Makefile.experiments), which may have other values: the open set's `make
# scenes` gives COLLECT_CALIBRATION on its command line (OPENSET_COLLECT_CALIBRATION, empty by
# default), so after `make all COLLECT_CALIBRATION=<ini>` it wrote these files back without the
# calibration, and `make -q all` was not clean (experiment-graph.md §6, "Two writers").
opts_real_goals := $(filter-out $(sub_make_goals),$(opts_thesis))
$(if $(opts_real_goals),$(call opts_kinds,$(OUT),real real-sim $(foreach k,$(REAL_ABL_PLACES),$(call \
  real_variant,$(k)))))

# real_rule(name, previous, out, classify.ini, model level): one tile's run into out/<name> (time-boxed,
# timed) after the run `previous` (its tile.time, or none) and, for a labelled tile, its score;
# GNU time's "Command exited with non-zero status" line is dropped from tile.time.
define real_rule
$(3)/$(1)/tile.time: $(call real_file,$(1)) $(REAL_DEPS) $(4) $(wildcard $(REAL_SHARE)/$(1).truth.json) \
    $(opts.$(notdir $(3))) \
    | $(2)
	$$(real_plus)@rm -rf '$(3)/$(1)' && mkdir -p '$(3)/$(1)' && s=0; \
	  $(call real_progress,add,$(1),$(3),$(4),$(5)); \
	  /usr/bin/time -f '%e %M %U %S' -o $$@.tmp timeout $(REAL_TIMEOUT) $$(REAL_SUBMAKE) \
	    $(call real_args,$(1),$(3),$(4),$(5)) || s=$$$$?; \
	  [ $$$$s -eq 0 ] || $(call real_progress,drop,$(1),$(3),$(4),$(5)); \
	  if [ $$$$s -eq 124 ]; then rm -f $(3)/$(1)/detections.json; \
	    echo "real  $(1): not finished after $(REAL_TIMEOUT) s (REAL_TIMEOUT), recorded as such"; \
	  elif [ $$$$s -eq 2 ]; then rm -f $(3)/$(1)/detections.json; \
	    echo "real  $(1): the workflow failed (a tool refused the tile: its .log in $(3)/$(1)/), recorded as such"; \
	  elif [ $$$$s -ne 0 ]; then rm -f $$@.tmp; echo "FAIL  real tile $(1) (exit $$$$s)"; exit $$$$s; fi; \
	  grep -v '^Command ' $$@.tmp >$$@.tmp2 && rm -f $$@.tmp && mv $$@.tmp2 $$@
	$(if $(wildcard $(REAL_SHARE)/$(1).truth.json),@[ ! -f $(3)/$(1)/detections.json ] || \
	  $(STAGE) $(3)/$(1)/score.json -- $(BIN)/score -d $(3)/$(1)/detections.json \
	  -t $(REAL_SHARE)/$(1).truth.json -o $(3)/$(1)/score.json)
	@echo "done  $$@ $$$$(cat $$@)"
endef
# real_chain(out, classify.ini, first previous, model level): the tiles one after another into out.
real_chain = $(eval real_last := $(3))$(foreach t,$(REAL_NAMES),$(eval $(call \
  real_rule,$(t),$(real_last),$(1),$(2),$(4)))$(eval real_last := $(1)/$(t)/tile.time))
REAL_RUNS := $(foreach t,$(REAL_NAMES),$(REAL_OUT)/$(t)/tile.time)
REAL_SIM_RUNS := $(foreach t,$(REAL_NAMES),$(REAL_SIM_OUT)/$(t)/tile.time)
REAL_ABL_RUNS := $(foreach k,$(REAL_ABL_PLACES),$(foreach t,$(REAL_NAMES),$(OUT)/$(call real_variant,$(k))/$(t)/tile.time))
$(call real_chain,$(REAL_OUT),$(REAL_CLASSIFY),,$(TILE_MODEL_DENSITY))
$(call real_chain,$(REAL_SIM_OUT),$(REAL_CLASSIFY_SIM),,$(TILE_MODEL_DENSITY))
# (classify's ablations after canopy's last tile, each after the one before: the tiles' wall
# times stay their own.)
real_abl_last := $(lastword $(REAL_RUNS))
$(foreach k,$(REAL_ABL_PLACES),$(call real_chain,$(OUT)/$(call real_variant,$(k)),$(call \
  real_abl_ini,$(k)),$(real_abl_last),$(call real_abl_density,$(k)))$(eval real_abl_last := $(OUT)/$(call real_variant,$(k))/$(lastword \
  $(REAL_NAMES))/tile.time))
.PHONY: real-tiles real-tiles-sim real-tiles-ablation
real-tiles: $(REAL_RUNS)
real-tiles-sim: $(REAL_SIM_RUNS)
real-tiles-ablation: $(REAL_ABL_RUNS)

# The report's "Real tiles" section: the tiles in order, the labels' directory, the time box.
ifeq ($(REAL_TILES),1)
all: real-tiles real-tiles-ablation
ifeq ($(REAL_ABLATION),1)
all: real-tiles-sim
endif
$(RES)/report.md: $(REAL_RUNS) $(REAL_ABL_RUNS)
# The tiles are records of the experiment's manifest (Makefile.experiments), in order, each
# with its hand labels when it has any and classify's ablations when they run (in order).
EXPERIMENT_REAL := $(foreach t,$(REAL_NAMES),$(call ml,$(strip real $(t) $(REAL_OUT)/$(t) $(wildcard \
  $(REAL_SHARE)/$(t).truth.json)))$(foreach k,$(REAL_ABL_PLACES),$(call ml,real-ablation $(t) $(OUT)/$(call \
  real_variant,$(k))/$(t) $(call real_abl_entry,$(k)))))
REPORT_ARGS += --real-timeout $(REAL_TIMEOUT)
endif
