# Whole tiles (issue 16; docs/decisions/scene-experiment.md), included at the end of
# Makefile.experiments.
#
#   make -f Makefile.experiments tile TILE=my.las MODELBASE=out/modelbase OUT=mytile/ -j2
#        [CRS=EPSG:32633] [TILE_CLASSIFY=share/params/classify.ini]
#
# one user tile -> mytile/detections.json (canopy.detections v2), mytile/detections.geojson,
# mytile/classes.ply (detect's classification: ground, other, candidate), mytile/top.png (the
# tile from above, highest point per pixel, detection footprints outlined; drawn from
# mytile/top.raster, the tile's heights, made beside the candidates) and per candidate
# mytile/cands/<id>/class.json (classify: the class-level answer, every candidate) and, for the
# candidates dense enough for model-level recognition (object density >= TILE_MODEL_DENSITY
# points/m², default 20: docs/decisions/density-scale.md), mytile/cands/<id>/{samples.pcd,
# mesh.ply, segments.json, segments.ply, match.json, verdict.json} (each with its .log and
# .time). MODELBASE is a directory of <model>.json graphs and <model>.pcd surfaces (`make -f
# Makefile.experiments verify-modelbase` builds out/modelbase). Every stage runs through
# $(STAGE), so LAUNCH=slurm launches them as jobs.
#
# How the candidates become targets: their number is known only after detect has run, so the
# tile's makefile is generated. `collect --plan` turns mytile/cands/index.json into
# mytile/cands.mk (TILE_CANDS := c0001 c0002 ...; TILE_TRANSFORM_<id> := 16 numbers;
# TILE_LEVEL_<id> := model or class, from the candidate's object density), which
# this file `-include`s. GNU make first brings every included makefile up to date (running
# detect and the plan when the tile or a tool changed), then re-reads the makefiles and only
# then builds the goals, now with one rule chain per candidate: the candidates run in
# parallel under -j, and a second run redoes only what changed (a changed share/params/
# <stage>.ini or tool re-runs that stage and what follows; a changed tile re-runs detect and
# so everything). Because make updates included makefiles even under -n and -q, a dry run
# (and the N/M progress count, which is a dry run) runs detect when it is out of date.
#
# A candidate whose chain fails in a tool's own error (e.g. cocone on a wire-thin object) is
# recorded as failed (stage.sh --record-failure: an empty artifact, so the later stages fail
# in turn and its verdict.json is empty); collect then answers it from its class.json (a failed
# model chain never hides a class-level answer), else counts it under "failed"; the tile goes on.

# The tools of this file, unless another fragment already has their build rule.
scene_tool_has_rule = $(or $(filter $(1),$(TOOLS)),$(and $(filter verify,$(1)),$(filter mk/verify.mk,$(MAKEFILE_LIST))))
$(foreach t,detect classify verify collect score topview,$(if $(call scene_tool_has_rule,$(t)),,$(eval $(call tool_rule,$(t)))))
# detect's parameters: $(P)/detect.ini when it exists (none today: detect's own defaults) for a
# user's tile, the real tiles and the open set's crops (TILE_DETECT); the scene experiment's runs
# take SCENE_DETECT (default the same), which the density ladder sets on its class-level rungs
# (mk/density.mk DENSITY_DETECT: share/params/detect-ladder.ini) and to each of its detect
# ablations. tile_detect is the one the make's runs take. (verify's parameters are
# share/params/verify.ini, the thesis protocol's, through scene_config.)
TILE_DETECT ?= $(wildcard $(P)/detect.ini)
SCENE_DETECT ?= $(TILE_DETECT)
$(foreach f,$(TILE_DETECT) $(SCENE_DETECT),$(if $(wildcard $(f)),,$(error detect's parameters: $(f) does not exist)))
tile_detect = $(TILE_DETECT)
# fitvox on candidates: airborne tiles are sparser than the thesis's renderings
# (share/params/fitvox-tile.ini says how the setting was chosen).
TILE_FITVOX ?= $(P)/fitvox-tile.ini
$(if $(wildcard $(TILE_FITVOX)),,$(error fitvox's parameters: TILE_FITVOX=$(TILE_FITVOX) does not exist))
# (These parameters' checks here are every goal's; for `make tile` and `make tiles`
# mk/tile-args.mk checks them first, before the progress count writes OUT: stop 71.)
# The object density (points per m² of a candidate's footprint, detect's index.json) from which
# a candidate also runs the model chain; below it classify's class-level answer alone
# (docs/decisions/density-scale.md: with the density rule below, 20 since stop 69, "The model
# level at 20 points/m², re-measured"; 50 from stop 49 to 68, the ablation the density ladder's
# class-level rungs and the real tiles run beside it; common/density_scale.h kModelLevelDensity).
# 370 is the value before the rule (fitvox-tile.ini's 6 points per 128 mm voxel,
# docs/decisions/classify.md §11).
TILE_MODEL_DENSITY ?= 20
ifneq ($(TILE_MODEL_DENSITY),20)
$(if $(shell printf '%s' '$(TILE_MODEL_DENSITY)' | grep -xE '[0-9]+(\.[0-9]+)?'),,$(error \
  TILE_MODEL_DENSITY=$(TILE_MODEL_DENSITY) must be a number of points/m²))
endif
# The model level's ablations (mk/density.mk DENSITY_DETECT_ABLATIONS, mk/real.mk
# REAL_CLASSIFY_ABLATIONS): model_entries_check(LIST, NAME) refuses an entry with "=" that is not
# TILE_MODEL_DENSITY=<number>; ablation_files(LIST): the list's parameter files (neither "-" nor
# such an entry).
model_entries_check = $(foreach e,$(1),$(if $(findstring =,$(e)),$(if $(shell printf '%s' '$(e)' | grep -xE \
  'TILE_MODEL_DENSITY=[0-9]+(\.[0-9]+)?'),,$(error $(2): $(e) is neither a parameter file nor \
  TILE_MODEL_DENSITY=<points/m²>))))
ablation_files = $(foreach e,$(filter-out -,$(1)),$(if $(findstring =,$(e)),,$(e)))
# The density rule (docs/decisions/density-scale.md): a model-level candidate below 370
# points/m² runs fitvox, cocone and ncut with lengths scaled to its density (the plan's
# <key>_<STAGE>_<id> options); TILE_DENSITY_SCALE=0 runs them all with the parameter files'
# lengths (the ablation; before the rule).
TILE_DENSITY_SCALE ?= 1
$(if $(filter-out 0 1,$(TILE_DENSITY_SCALE)),$(error TILE_DENSITY_SCALE=$(TILE_DENSITY_SCALE): must be 0 or 1))
scene_config = $(if $(wildcard $(P)/$(1).ini),--config $(P)/$(1).ini)
# The classes of the thesis models (their modelbase entries have no <model>.class file): classify
# takes a modelbase entry with a class as one more class range (classify.md §12); collect writes
# a model answer without a class with its model's class and group (stop 69: the real tiles'
# class right counts it by its group, as a class answer's).
MODEL_CLASSES ?= share/models/classes.csv
$(if $(wildcard $(MODEL_CLASSES)),,$(error MODEL_CLASSES=$(MODEL_CLASSES) does not exist))
# classify's parameters: a user's tile and the real tiles take the defaults (share/params/
# classify.ini, calibrated on real development tiles); the simulated scene experiment keeps the
# thresholds fitted on simulated tiles (classify-sim.ini; docs/decisions/classify.md §5).
TILE_CLASSIFY ?= $(P)/classify.ini
SCENE_CLASSIFY ?= $(P)/classify-sim.ini
# The confidence each final answer states (docs/decisions/verify.md §16): collect maps the
# answering level's confidence through COLLECT_CALIBRATION's Platt map for its source (model,
# class, verify's none, classify's none; fitted on development tiles by bench/collect/
# calibrate.py), so it is calibrated for the final answer. COLLECT_CALIBRATION= (empty) states
# each level's own confidence (the ablation; before §16). Never changes which answer is given.
# The fit is a statement about the population it was fitted on: simulated tiles whose vehicles
# are in the modelbase. So it is the default of the scene experiment alone; `make tile` (a user's
# tile, the real tiles) and the open set (mk/openset.mk: unseen vehicles, where it overstates:
# verify.md §16) state each level's own confidence unless COLLECT_CALIBRATION is given.
ifneq ($(filter tile,$(MAKECMDGOALS)),)
COLLECT_CALIBRATION ?=
else
COLLECT_CALIBRATION ?= $(P)/calibration.ini
endif
$(if $(COLLECT_CALIBRATION),$(if $(wildcard $(COLLECT_CALIBRATION)),,$(error \
  COLLECT_CALIBRATION=$(COLLECT_CALIBRATION) does not exist)))
collect_calibration = $(if $(COLLECT_CALIBRATION), --calibration $(COLLECT_CALIBRATION))
# (A file under OUT is generated by its own rule, e.g. the open set's, mk/openset.mk; a dry run
# does not write it.)
# SCENE_CLASSIFY_ABLATIONS=<ini> ...: classify run again on every candidate with each of these
# parameter files, collected and scored beside canopy's (the report shows a changed default
# beside its ablation): the list's K-th entry is the variant class-ablation (K = 1) or
# class-ablation-K (cands/<id>/class-ablation-K.json, detections-class-ablation-K.json,
# $(SCENE_RES)/class-ablation-K/score.json, the options kind classify-ablation-K). An entry "-"
# leaves its place empty (that variant not run; the later ones keep their names). Empty, the
# default, leaves them out; the density ladder sets it (mk/density.mk), the open set through the
# numbered names below.
SCENE_CLASSIFY_ABLATIONS ?=
# SCENE_CLASSIFY_ABLATION, SCENE_CLASSIFY_ABLATION_2, SCENE_CLASSIFY_ABLATION_3: the list's first
# three places by name, as mk/openset.mk gives them to its sub-makes (the envelope alone off, the
# family entries alone 1: each may be empty, and a later one set) and docs' commands turn them off
# (SCENE_CLASSIFY_ABLATION=): when one is not empty they are the list (an empty one "-"); not
# together with SCENE_CLASSIFY_ABLATIONS.
scene_class_named := $(strip $(SCENE_CLASSIFY_ABLATION) $(SCENE_CLASSIFY_ABLATION_2) $(SCENE_CLASSIFY_ABLATION_3))
$(if $(and $(scene_class_named),$(strip $(SCENE_CLASSIFY_ABLATIONS))),$(error SCENE_CLASSIFY_ABLATIONS and \
  SCENE_CLASSIFY_ABLATION[_2|_3] given together: give the list alone))
scene_class_list := $(if $(scene_class_named),$(or $(SCENE_CLASSIFY_ABLATION),-) $(or $(SCENE_CLASSIFY_ABLATION_2),-) \
  $(or $(SCENE_CLASSIFY_ABLATION_3),-),$(SCENE_CLASSIFY_ABLATIONS))
# list_numbers(LIST): 1 2 ... N, one per word of LIST. list_places(LIST): the numbers of its
# entries that are not "-". class_variant(K): the classify ablation at place K (class-ablation,
# class-ablation-2, ...). Used by mk/density.mk and mk/real.mk too.
list_numbers = $(if $(1),$(call list_numbers,$(wordlist 2,$(words $(1)),$(1))) $(words $(1)))
list_places = $(foreach k,$(call list_numbers,$(1)),$(if $(filter-out -,$(word $(k),$(1))),$(k)))
class_variant = class-ablation$(if $(filter-out 1,$(1)),-$(1))
# The classify ablations asked for, by variant, and each variant's parameters (scene_class_ini.VARIANT).
SCENE_CLASS_ABLATIONS := $(foreach k,$(call list_places,$(scene_class_list)),$(call class_variant,$(k)))
$(foreach k,$(call list_places,$(scene_class_list)),$(eval \
  scene_class_ini.$(call class_variant,$(k)) := $(word $(k),$(scene_class_list))))
# SCENE_COLLECT_ABLATIONS=<entry> ...: collect run again on every run with each entry's options,
# from the same verdicts and class answers, scored beside canopy's. An entry is collect's options
# joined by commas, each as --name=value (`--contradicted-below=0,--refused-below=0`: a value holds
# no comma or space; bench/openset/recollect.py writes them the same way). The list's K-th entry is
# the variant collect-ablation (K = 1) or collect-ablation-K (detections-collect-ablation-K.json,
# $(SCENE_RES)/collect-ablation-K/score.json, the options kind collect-ablation-K); an entry "-"
# leaves its place empty (the later ones keep their names). The open set gives the list
# (mk/openset.mk OPENSET_COLLECT_ABLATIONS: the model answer first, the contradiction by class).
# SCENE_COLLECT_ABLATION=<collect options, separated by spaces>: the list's first place by name,
# the list when it is not given (the scene experiment's): with a calibration the default is
# --coarse-none-below=0 (docs/decisions/verify.md §19: one none map for every verify none, the
# statement before the density split), whose reliability table the report shows beside canopy's
# (report --tile-collect-ablation, the first place alone); without one, empty (the split states
# nothing then). Empty leaves it out; the density ladder empties it (mk/density.mk). Not given
# (not empty) together with SCENE_COLLECT_ABLATIONS.
SCENE_COLLECT_ABLATION ?= $(if $(COLLECT_CALIBRATION),--coarse-none-below=0)
comma := ,
SCENE_COLLECT_ABLATIONS ?= $(subst $(space),$(comma),$(strip $(SCENE_COLLECT_ABLATION)))
$(if $(and $(filter command line environment override,$(origin SCENE_COLLECT_ABLATIONS)),$(filter command line \
  environment override,$(origin SCENE_COLLECT_ABLATION)),$(strip $(SCENE_COLLECT_ABLATION))),$(error \
  SCENE_COLLECT_ABLATIONS and SCENE_COLLECT_ABLATION given together: give the list alone))
# collect_variant(K): the collect ablation at place K (collect-ablation, collect-ablation-2, ...).
# The collect ablations asked for, by variant, and each one's options (scene_collect_opts.VARIANT,
# separated by spaces).
collect_variant = collect-ablation$(if $(filter-out 1,$(1)),-$(1))
scene_collect_list := $(SCENE_COLLECT_ABLATIONS)
SCENE_COLLECT_VARIANTS := $(foreach k,$(call list_places,$(scene_collect_list)),$(call collect_variant,$(k)))
$(foreach k,$(call list_places,$(scene_collect_list)),$(eval scene_collect_opts.$(call collect_variant,$(k)) := $(subst \
  $(comma),$(space),$(word $(k),$(scene_collect_list)))))
# SCENE_VERIFY_ABLATION=<verify options, each as --name=value>: verify run a second time on every
# candidate that reached the model chain, with these options after its parameters
# (cands/<id>/verdict-ablation.json), collected from those verdicts and the same class answers
# and scored beside canopy's as $(SCENE_RES)/verify-ablation/score.json. Empty, the default,
# leaves it out; the density ladder sets it (mk/density.mk DENSITY_VERIFY_ABLATION).
SCENE_VERIFY_ABLATION ?=
# verify_options_check(VARIABLE): an error naming VARIABLE unless its value is verify's options, each
# as --name=value (the scene experiment's, the density ladder's and the open set's verify ablations).
verify_options_check = $(if $(filter-out --%,$($(1))),$(error $(1)=$($(1)): verify's options, each as --name=value))
$(foreach f,$(TILE_CLASSIFY) $(SCENE_CLASSIFY) $(filter-out -,$(scene_class_list)),$(if $(wildcard $(f))$(filter $(OUT)/%,$(f)),,$(error classify's parameters: $(f) does not exist)))

# The tile workflow's options as prerequisites (the options files, Makefile.experiments): one
# text per stage kind, its file under the set of runs' directory (the tile's OUT, SCENE_DIR, the
# open set's crops), written by tile_opts_kinds(DIR) in each of those makes. The model chain
# (fitvox | cocone | ncut | gmatch | verify) is one kind: a change of any of its options re-runs
# fitvox, and so the rest. tile_classify is classify's parameters in that make (TILE_CLASSIFY
# or SCENE_CLASSIFY); opts_text_topview is the make's own (TOP_RASTER for `make tile`,
# SCENE_TOPVIEW_SIZE for the scene experiment's pictures).
# tile_inputs_detect, tile_inputs_modelbase: the `tile` target's own lines (below; empty for
# every other make): which tile and modelbase the run read. (gmatch and verify read the modelbase
# and verify the trajectory through the `tile` target's own kinds, tile-modelbase and
# tile-trajectory, so that neither re-runs fitvox.)
opts_text_detect = $(call opts_line,config,$(if $(tile_detect),--config $(tile_detect)))$(tile_inputs_detect)
opts_text_plan = $(call opts_line,model-density,$(TILE_MODEL_DENSITY))$(call opts_line,density-scale,$(TILE_DENSITY_SCALE))
opts_text_classify = $(call opts_line,parameters,$(tile_classify))$(call opts_line,model-classes,$(MODEL_CLASSES))$(tile_inputs_modelbase)
# (each classify ablation's: opts_text_classify-ablation, opts_text_classify-ablation-2, ...)
$(foreach v,$(SCENE_CLASS_ABLATIONS),$(eval opts_text_$(patsubst class-%,classify-%,$(v)) = $$(call \
  opts_line,parameters,$(scene_class_ini.$(v)))$$(call opts_line,model-classes,$$(MODEL_CLASSES))))
opts_text_models = $(call opts_line,fitvox,$(TILE_FITVOX))$(call opts_line,parameters,$(P))$(call \
  opts_line,density-scale,$(TILE_DENSITY_SCALE))
opts_text_collect = $(call opts_line,calibration,$(COLLECT_CALIBRATION))$(call opts_line,crs,$(CRS))$(call \
  opts_line,model-classes,$(MODEL_CLASSES))$(tile_inputs_modelbase)
# (each collect ablation's: opts_text_collect-ablation, opts_text_collect-ablation-2, ...)
$(foreach v,$(SCENE_COLLECT_VARIANTS),$(eval opts_text_$(v) = $$(call opts_line,options,$(scene_collect_opts.$(v)))$$(call \
  opts_line,calibration,$$(COLLECT_CALIBRATION))))
opts_text_verify-ablation = $(call opts_line,options,$(SCENE_VERIFY_ABLATION))
tile_opts_kinds = $(call opts_kinds,$(1),detect plan classify models collect$(if $(value opts_text_topview), topview)$(patsubst \
  class-%, classify-%,$(SCENE_CLASS_ABLATIONS))$(foreach v,$(SCENE_COLLECT_VARIANTS), $(v))$(if \
  $(SCENE_VERIFY_ABLATION), verify-ablation))

# read_plan(FILE): a generated candidate plan. A real run includes it, so make remakes it first
# (detect, the plan) and re-reads the makefiles; a dry run (-n, -q, -t) reads it as it is and
# never remakes it, so `make -q` answers without detecting (a stale plan still makes -q answer
# 1: detections.json depends on it) and `make -n` shows the candidates known so far.
read_plan = $(if $(dry_run),$(if $(wildcard $(1)),$(eval $(file <$(1)))),$(eval -include $(1)))
# read_tile_plan(FILE): read_plan for the tile workflow (`make tile`, one tile; `make tiles` and
# the real tiles run it per tile): a real run includes the plan with `include`, so a detect or a
# plan step that fails stops make there, with the tool's own error and make's "Error" line. With
# -include make went on to the goals and GNU make (4.3) then reported the file that had failed as
# "No rule to make target '<OUT>/cands/index.json', needed by '<OUT>/cands.mk'" below the real
# error (hardening.md, stop 67). A plan not there yet is first made empty and dated 1970, older
# than any index.json (so always remade): `include` of a missing file whose remake fails also
# says "<OUT>/cands.mk: No such file or directory". The experiment's tiles keep read_plan.
read_tile_plan = $(if $(dry_run),$(call read_plan,$(1)),$(if $(wildcard $(1)),,$(shell mkdir -p $(dir $(1)) && \
  touch -d @86400 $(1)))$(eval include $(1)))

# tile_rules(KEY, DIR, SCAN, MODELBASE[, DETECT OPTIONS]): detect, the plan and the
# classification (classes.ply: a hard link to detect's, where the filesystem has them; touched,
# since the link has the time detect wrote it, just before index.json).
define tile_rules
$(2)/cands/index.json: $(3) $(call tool,detect) $(tile_detect) $(opts.detect)
	@$(STAGE) $(2)/detect -- $(BIN)/detect$(if $(tile_detect), --config $(tile_detect)) $(5) -i $(3) -o $(2)/cands
$(2)/cands.mk: $(2)/cands/index.json $(call tool,collect) $(opts.plan)
	@$(STAGE) $$@ -- $(BIN)/collect -i $(2)/cands/index.json --plan $$@ --plan-key $(1) \
	  --model-density $(TILE_MODEL_DENSITY)$(if $(filter 0,$(TILE_DENSITY_SCALE)), --no-density-scale)
	@[ -z "$$$$CANOPY_PROGRESS" ] || scripts/progress.sh extend "$$$$CANOPY_PROGRESS" $$@ $$(TILE_CAND_KINDS)
$(2)/classes.ply: $(2)/cands/index.json
	@$(call link_or_copy,$(2)/cands/classes.ply,$$@) && touch -c $$@ && echo "done  $$@"
endef

# The stages each candidate runs, as scripts/progress.sh names their kinds (the plan step adds
# them to the progress count: the candidates are known only once detect has run).
TILE_CAND_KINDS := classify:cand/class.json fitvox:cand/samples.pcd cocone:cand/mesh.ply ncut:cand/segments.json \
  gmatch:cand/match.json verify:cand/verdict.json

# class_rule(DIR, ID, INI, MODELBASE[, NAME]): classify with the parameters INI on one candidate
# (every candidate; exit 1 only on a bad file: too sparse is an answer, so no --record-failure)
# into cands/<id>/NAME (class.json; an ablation's class-ablation[-K].json, whose options file is
# classify-ablation[-K]). The modelbase's entries with a class (<model>.class, or
# MODEL_CLASSES for the thesis models) are class ranges beside the families' (docs/decisions/
# classify.md §12).
define class_rule
$(1)/cands/$(2)/$(or $(5),class.json): $(1)/cands/index.json $(call tool,classify) $(3) \
    $(wildcard $(4)/*.json $(4)/*.pcd $(4)/*.class) $(MODEL_CLASSES) $(if $(5),$(opts.classify-$(patsubst class-%.json,%,$(5))),$(opts.classify))
	@$(STAGE) $$@ -- $(BIN)/classify --config $(3) -i $(1)/cands/$(2).pcd \
	  --index $(1)/cands/index.json --modelbase $(4) --model-classes $(MODEL_CLASSES) -o $$@
endef
# collect_variant_rule(DIR, KEY, MODELBASE, VARIANT, CLASS, VERDICT, BEFORE, AFTER, PREREQS): the
# run's detections collected another way, as detections-VARIANT.json: from every candidate's
# cands/<id>/CLASS and every model-level candidate's cands/<id>/VERDICT (none when VERDICT is
# empty), with collect's options BEFORE (ahead of -o) and AFTER (after --modelbase), PREREQS
# more prerequisites. One rule for every variant: classify's and collect's ablations, the
# baseline's methods, the size-only classifier (scored by variant_score_rule below).
# (VARIANT, CLASS and VERDICT are stripped: a call may break its line before them.)
define collect_variant_rule
$(1)/detections-$(strip $(4)).json: $(1)/cands.mk $(foreach c,$($(2)_CANDS),$(1)/cands/$(c)/$(strip $(5))) \
    $(if $(strip $(6)),$(foreach c,$(call model_cands,$(2)),$(1)/cands/$(c)/$(strip $(6)))) $(9) $(call tool,collect) \
    $(MODEL_CLASSES)
	@$(STAGE) $$@ -- $(BIN)/collect -i $(1)/cands/index.json $(7) --model-classes $(MODEL_CLASSES) -o $$@ --modelbase $(3) $(8)
endef
# class_ablation_rules(DIR, KEY, MODELBASE, INI[, VARIANT]): classify's ablation VARIANT
# (class-ablation, the default, or class-ablation-K) on every candidate of a run
# (cands/<id>/VARIANT.json, with the parameters INI) and the run's detections with it
# (detections-VARIANT.json: the model chain's verdicts as in detections.json, the class answers
# from the ablation's files; collect --class-name). SCENE_CLASSIFY_ABLATIONS above.
class_ablation_rules = $(foreach c,$($(2)_CANDS),$(eval $(call class_rule,$(1),$(c),$(4),$(3),$(or $(5),class-ablation).json)))$(eval \
  $(call collect_variant_rule,$(1),$(2),$(3),$(or $(5),class-ablation),$(or $(5),class-ablation).json,verdict.json,--class-name \
  $(or $(5),class-ablation).json$(collect_calibration),,$(COLLECT_CALIBRATION) $(opts.collect)))
# class_ablations(RUNS, MODELBASE, SET_DIR, MANIFEST, SET_RES, CLASSES): every classify ablation asked
# for (SCENE_CLASS_ABLATIONS) on every run of RUNS, then each one's score of the set (variant_score_rule):
# the scene experiment's runs below, the open set's crops (mk/openset.mk).
class_ablations = $(foreach v,$(SCENE_CLASS_ABLATIONS),$(foreach r,$(1),$(call class_ablation_rules,$(r),$(call \
  scene_key,$(r)),$(2),$(scene_class_ini.$(v)),$(v)))$(eval $(call variant_score_rule,$(v),$(3),$(4),$(1),$(5),$(6))))
# collect_ablation_rules(DIR, KEY, MODELBASE, OPTIONS[, VARIANT]): the run's detections collected
# with OPTIONS (separated by spaces) as detections-VARIANT.json (collect-ablation, the default, or
# collect-ablation-K). SCENE_COLLECT_ABLATIONS above; collect_ablations below.
collect_ablation_rules = $(eval $(call collect_variant_rule,$(1),$(2),$(3),$(or $(5),collect-ablation),class.json,verdict.json,,$(4)$(collect_calibration),$(COLLECT_CALIBRATION) \
  $(opts.$(or $(5),collect-ablation))))
# collect_ablations(RUNS, MODELBASE, SET_DIR, MANIFEST, SET_RES, CLASSES): every collect ablation
# asked for (SCENE_COLLECT_VARIANTS) on every run of RUNS, then each one's score of the set
# (variant_score_rule): the scene experiment's runs below, the open set's crops (mk/openset.mk).
collect_ablations = $(foreach v,$(SCENE_COLLECT_VARIANTS),$(foreach r,$(1),$(call collect_ablation_rules,$(r),$(call \
  scene_key,$(r)),$(2),$(scene_collect_opts.$(v)),$(v)))$(eval $(call variant_score_rule,$(v),$(3),$(4),$(1),$(5),$(6))))
# verify_ablation_rules(DIR, KEY, MODELBASE, OPTIONS): verify's ablation on every model-level
# candidate of a run (cands/<id>/verdict-ablation.json, with OPTIONS) and the run's detections
# with it (detections-verify-ablation.json: the same class answers, those verdicts; collect
# --verdict-name). SCENE_VERIFY_ABLATION below.
verify_ablation_rules = $(foreach c,$(call model_cands,$(2)),$(eval $(call verify_rule,$(1),$(c),$(2),$(3),verdict-ablation.json,$(4))))$(eval \
  $(call collect_variant_rule,$(1),$(2),$(3),verify-ablation,class.json,verdict-ablation.json,--verdict-name \
  verdict-ablation.json$(collect_calibration),,$(COLLECT_CALIBRATION) $(opts.collect)))
# variant_score_rule(VARIANT, DIR, MANIFEST, RUNS, RES, CLASSES): the score of every run's
# detections-VARIANT.json as RES/VARIANT/score.json, over DIR/tiles-VARIANT.txt (the score's tile
# list MANIFEST with each run's detections.json so renamed), CLASSES the model classes (score
# names a missing file itself: a prerequisite only when it exists).
define variant_score_rule
$(2)/tiles-$(1).txt: $(call text_prereq,$(2)/tiles-$(1).txt,$(subst /detections.json ,/detections-$(1).json ,$(3)))
$(5)/$(1)/score.json: $(2)/tiles-$(1).txt $(addsuffix /detections-$(1).json,$(4)) $(call tool,score) $(wildcard $(6)) \
    $(opts.score)
	@$(STAGE) $$@ -- $(BIN)/score --tiles $(2)/tiles-$(1).txt --model-classes $(6) -o $$@ --csv $(5)/$(1)/
endef
# is_model(KEY, ID): non-empty when the plan sends the candidate through the model chain (an
# older plan without levels: every candidate).
is_model = $(filter-out class,$($(1)_LEVEL_$(2)))$(if $($(1)_LEVEL_$(2)),,model)
# model_cands(KEY): the candidates of the plan that run the model chain.
model_cands = $(foreach c,$($(1)_CANDS),$(if $(call is_model,$(1),$(c)),$(c)))
# cand_rules(DIR, KEY, MODELBASE, SEEDKEY, CLASSIFY_INI): class_rule for every candidate,
# cand_rule for the model-level ones.
cand_rules = $(foreach c,$($(2)_CANDS),$(eval $(call class_rule,$(1),$(c),$(5),$(3))))$(foreach \
  c,$(call model_cands,$(2)),$(eval $(call cand_rule,$(1),$(c),$(2),$(3),$(4))))

# cand_scale(KEY, STAGE, ID): " <options>" of the density rule for the stage (the plan's
# <KEY>_<STAGE>_<ID>: common/density_scale.h, docs/decisions/density-scale.md), after its
# --config so they override the file's lengths; "" for a candidate at the dense end (today's
# command line).
cand_scale = $(if $($(1)_$(2)_$(3)), $($(1)_$(2)_$(3)))
# cand_rule(DIR, ID, KEY, MODELBASE, SEEDKEY): fitvox | cocone | ncut | gmatch | verify on one
# candidate (cands/<id>.pcd, written by detect with index.json), with the lengths the plan's
# density rule gives it. With <KEY>_TRAJECTORY set (the
# tile target's TRAJECTORY=), verify takes the sensor directions from that trajectory and
# re-runs when it changes; no other key sets it, so the scene experiment's rules are unchanged.
define cand_rule
$(1)/cands/$(2)/samples.pcd: $(1)/cands/index.json $(call tool,fitvox) $(TILE_FITVOX) $(opts.models)
	@$(STAGE) --record-failure $$@ -- $(BIN)/fitvox --config $(TILE_FITVOX)$(call cand_scale,$(3),FITVOX,$(2)) \
	  --pcd-encoding $(PCD_ENCODING) -i $(1)/cands/$(2).pcd -o $$@
$(1)/cands/$(2)/mesh.ply: $(1)/cands/$(2)/samples.pcd $(call tool,cocone) $(P)/cocone.ini $(opts.models)
	@$(STAGE) --record-failure $$@ -- $(BIN)/cocone --config $(P)/cocone.ini$(call cand_scale,$(3),COCONE,$(2)) -i $$< -o $$@
$(1)/cands/$(2)/segments.json: $(1)/cands/$(2)/mesh.ply $(call tool,ncut) $(P)/ncut.ini $(opts.models)
	@$(STAGE) --record-failure $$@ -- $(BIN)/ncut --config $(P)/ncut.ini$(call cand_scale,$(3),NCUT,$(2)) \
	  --seed $$(call seed,$(5)/$(2)) -i $$< -o $$@ --colored $(1)/cands/$(2)/segments.ply
$(1)/cands/$(2)/match.json: $(1)/cands/$(2)/segments.json $(wildcard $(4)/*.json) $(call tool,gmatch) $(P)/gmatch.ini \
    $(opts.models) $(opts.tile-modelbase)
	@$(STAGE) --record-failure $$@ -- $(BIN)/gmatch --config $(P)/gmatch.ini -i $$< --modelbase $(4) -o $$@
$(call verify_rule,$(1),$(2),$(3),$(4),verdict.json)
endef
# verify_rule(DIR, ID, KEY, MODELBASE, NAME[, OPTIONS[, FPFH]]): verify on one model-level
# candidate into cands/<id>/NAME, with OPTIONS after its parameters (SCENE_VERIFY_ABLATION's
# verdict-ablation.json, which also depends on those options' file). The hypotheses are gmatch's
# (match.json, with the segment graph for its pairs) or, with FPFH non-empty, the fpfh baseline's
# ranking and poses (hypotheses-fpfh.json, which its stage writes beside baseline-fpfh.json: the
# rule depends on that; no segment graph: the list has no pairs).
define verify_rule
$(1)/cands/$(2)/$(5): $(1)/cands/$(2)/$(if $(7),baseline-fpfh.json,match.json) $(1)/cands/$(2)/samples.pcd \
    $(wildcard $(4)/*.json $(4)/*.pcd) $(call tool,verify) $(wildcard $(P)/verify.ini) $($(3)_TRAJECTORY) $(opts.models) \
    $(opts.tile-modelbase) $(opts.tile-trajectory)$(if \
    $(6), $(opts.verify-ablation))$(if $(7), $(MODELBASE) $(VERIFY_SURFACES))
	@$(STAGE) --record-failure $$@ -- $(BIN)/verify $(call scene_config,verify)$(if $(6), $(6)) \
	  -i $(1)/cands/$(2)/$(if $(7),hypotheses-fpfh.json,match.json) --points $(1)/cands/$(2)/samples.pcd$(if \
	  $(7),, --segments $(1)/cands/$(2)/segments.json) \
	  --modelbase $(4) --transform $($(3)_TRANSFORM_$(2))$(if $($(3)_TRAJECTORY), --trajectory $($(3)_TRAJECTORY)) -o $$@
endef

# tile_collect(KEY, DIR, MODELBASE, SCAN): every class.json and model-level verdict ->
# detections.json + GeoJSON, and the top-view picture of the tile with the detections' footprints.
# (The `tile` target shows collect's one-line summary and warning from detections.json.log: below.)
# For the `tile` target (KEY TILE) the picture comes from the tile's height raster (top.raster:
# topview --raster-out, which needs only the tile, so it runs beside the candidates' chains),
# drawn with the footprints once the detections are in: the same picture as from the tile,
# the tile read off the end of the run (docs/decisions/cost.md §17). TOP_RASTER=0: topview on
# the tile at the end, the rule before (and every other key's).
TOP_RASTER ?= 1
define tile_collect
$(2)/detections.json: $(2)/cands.mk $(foreach c,$($(1)_CANDS),$(2)/cands/$(c)/class.json) \
    $(foreach c,$(call model_cands,$(1)),$(2)/cands/$(c)/verdict.json) $(call tool,collect) $(COLLECT_CALIBRATION) \
    $(MODEL_CLASSES) $(opts.collect)
	@$(STAGE) $$@ -- $(BIN)/collect -i $(2)/cands/index.json -o $$@ --geojson $(2)/detections.geojson \
	  --modelbase $(3) --model-classes $(MODEL_CLASSES) $(if $(CRS),--crs $(CRS))$(collect_calibration)
ifeq ($(1)$(if $(filter 0,$(TOP_RASTER)),,1),TILE1)
$(2)/top.raster: $(4) $(call tool,topview) $(opts.detect)
	@$(STAGE) $$@ -- $(BIN)/topview -i $(4) --raster-out $$@
$(2)/top.png: $(2)/detections.json $(2)/top.raster $(call tool,topview) $(opts.topview)
	@$(STAGE) $$@ -- $(BIN)/topview --raster $(2)/top.raster --detections $(2)/detections.json -o $$@
else
$(2)/top.png: $(2)/detections.json $(4) $(call tool,topview) $(opts.topview) $(opts.detect)
	@$(STAGE) $$@ -- $(BIN)/topview -i $(4) --detections $(2)/detections.json -o $$@
endif
endef

.PHONY: tile
ifneq ($(filter tile,$(MAKECMDGOALS)),)
# (TILE, OUT, MODELBASE, CRS and TRAJECTORY are checked by mk/tile-args.mk, before the progress
# count writes anything.)
TILE_OUT := $(patsubst %/,%,$(OUT))
TILE_MB := $(patsubst %/,%,$(MODELBASE))
TILE_TRAJECTORY := $(TRAJECTORY)
# Which files the run read, in the options texts (stop 70): a second `make tile` into the same
# OUT with another TILE (an older file too, or the same name replaced), another MODELBASE, or
# another TRAJECTORY or none re-runs the stages that read it; before, the prerequisites' times
# alone decided, and such a run said "Nothing to be done" and kept the first run's results. A
# file by its real path (links followed), size and modification time; the modelbase by its
# directory's real path and, since stop 71 (review F21), its entries: one line "entry = <file>
# <size> <mtime>" per <model>.json, .pcd and .class file (links followed; one stat for them all),
# the files gmatch, verify, classify and collect read. Before, a change inside the modelbase was
# seen only through its files' times as prerequisites: an entry removed (user-modelbase prunes
# entries) or replaced by an older file (mv, cp -p, tar x) left the tile "up to date", its
# detections naming a model no longer there. Only the kinds that read the modelbase carry these
# lines (classify, collect, tile-modelbase: gmatch and verify), so detect and fitvox | cocone |
# ncut do not re-run. (The scene experiment's tiles have no such lines: their modelbase is the
# experiment's own, a prerequisite made by the same make.)
file_identity = $(realpath $(1)) $(shell stat -L -c '%s %Y' '$(1)' 2>/dev/null)
tile_inputs_detect = $(call opts_line,tile,$(call file_identity,$(TILE)))
TILE_MB_FILES := $(sort $(notdir $(wildcard $(TILE_MB)/*.json $(TILE_MB)/*.pcd $(TILE_MB)/*.class)))
TILE_MB_ENTRIES := $(if $(TILE_MB_FILES),$(shell cd '$(TILE_MB)' && stat -L -c '%n/%s/%Y' $(TILE_MB_FILES) 2>/dev/null))
tile_inputs_modelbase = $(call opts_line,modelbase,$(realpath $(TILE_MB)))$(subst $(nl) ,$(nl),$(foreach \
  e,$(TILE_MB_ENTRIES),$(call opts_line,entry,$(subst /, ,$(e)))))
opts_text_tile-modelbase = $(tile_inputs_modelbase)
opts_text_tile-trajectory = $(call opts_line,trajectory,$(if $(TILE_TRAJECTORY),$(call file_identity,$(TILE_TRAJECTORY))))
tile_classify := $(TILE_CLASSIFY)
opts_text_topview = $(call opts_line,raster,$(TOP_RASTER))
$(call tile_opts_kinds,$(TILE_OUT))
$(call opts_kinds,$(TILE_OUT),tile-modelbase tile-trajectory)
$(eval $(call tile_rules,TILE,$(TILE_OUT),$(TILE),$(TILE_MB)))
$(call read_tile_plan,$(TILE_OUT)/cands.mk)
$(call cand_rules,$(TILE_OUT),TILE,$(TILE_MB),$(notdir $(TILE)),$(TILE_CLASSIFY))
$(eval $(call tile_collect,TILE,$(TILE_OUT),$(TILE_MB),$(TILE)))
# What the tile holds, every time the goal is made (stop 71: a second `make tile` with nothing to
# do said only "Nothing to be done for 'tile'"): collect's lines of the run that wrote
# detections.json — its one-line summary, its warning (what the data supports) and its notes
# (no CRS, ...) — each led by the tile's output directory, read from detections.json.log, where
# the stage runner kept them: the user reads what happened without opening the log, and a re-run
# shows it again without running collect (the scene experiment's tiles leave them in their
# logs). No recipe under a dry run: `make -q tile` answers 0 when all is up to date.
tile: $(TILE_OUT)/detections.json $(TILE_OUT)/classes.ply $(TILE_OUT)/top.png$(if $(dry_run),, ; \
  @[ ! -f $(TILE_OUT)/detections.json.log ] || sed -n 's|^collect: |$(TILE_OUT): |p' $(TILE_OUT)/detections.json.log)
# TRAJECTORY's format, checked before detect runs (stop 71: a file that is not a trajectory ran
# detect, classify and every model chain, every verify then failed, and the run ended exit 0):
# verify --check-trajectory reads it with verify's own reader (formats::read_trajectory), so the
# check and the use cannot disagree. An order-only prerequisite of the index: it runs first, and
# a change of the trajectory re-runs verify alone, as before (the tile-trajectory options kind).
# Not under a dry run (`make -q` would always answer 1).
ifneq ($(TILE_TRAJECTORY),)
.PHONY: tile-trajectory-check
$(TILE_OUT)/cands/index.json: | tile-trajectory-check
tile-trajectory-check: $(call tool,verify)$(if $(dry_run),, ; @$(BIN)/verify -q --check-trajectory \
  $(TILE_TRAJECTORY) || { echo "tile: TRAJECTORY=$(TILE_TRAJECTORY) is not a canopy trajectory \
  (formats/README.md \"Trajectory\"): nothing was run" >&2; exit 1; })
endif
endif

# A directory of tiles (a survey campaign):
#   make -f Makefile.experiments tiles TILES=dir/ MODELBASE=out/modelbase OUT=batch/ -j8 [LAUNCH=slurm]
# runs the `tile` workflow on every dir/*.las, dir/*.laz and dir/*.pcd (the extension in either
# case) into batch/<name>/ (name = the file name without its extension), one sub-make per tile
# sharing make's job slots, so tiles and their candidates run in parallel; LAUNCH, CRS and the
# other variables pass through. A tile's trajectory is TRAJECTORY= when given (one file for the
# whole flight), else dir/<name>.traj when there is one (what rangetrace writes beside a sensor
# tile). A tile that fails stops the batch, as make does; `make -k tiles ...` goes on with the
# others and exits 2 at the end.
.PHONY: tiles
ifneq ($(filter tiles,$(MAKECMDGOALS)),)
# (TILES, OUT and TILES_FILES, the tiles, by mk/tile-args.mk. LAZ is read wherever LAS is,
# docs/decisions/laz.md; before stop 66 a directory of .laz tiles held "no .las or .pcd file".)
TILES_OUT := $(patsubst %/,%,$(OUT))
define tiles_rule
.PHONY: tiles-$(basename $(notdir $(1)))
tiles-$(basename $(notdir $(1))):
	+@$$(MAKE) --no-print-directory -f Makefile.experiments tile TILE=$(1) \
	  OUT=$(TILES_OUT)/$(basename $(notdir $(1))) MODELBASE=$(MODELBASE) PROGRESS=0 \
	  $(if $(TRAJECTORY),,$(if $(wildcard $(basename $(1)).traj),TRAJECTORY=$(basename $(1)).traj))
endef
$(foreach f,$(TILES_FILES),$(eval $(call tiles_rule,$(f))))
tiles: $(foreach f,$(TILES_FILES),tiles-$(basename $(notdir $(f))))
endif

# ---- the scene experiment (issue 16), part of `all` -----------------------------------------
#   make -f Makefile.experiments scenes -j2 [SCENE_SEEDS="101 102" SCENE_COVERS=light SCENE_NOISES=0]
# Seeded tiles x cover level x noise -> detect -> per candidate fitvox | cocone | ncut | gmatch |
# verify -> collect -> score:
#   out/scenes/<cover>/tile-<seed>/recipe.scene, scan.pcd, truth.json   rendered once
#   out/scenes/<cover>/tile-<seed>/noise-<mm>/scan.pcd                    + noise
#   out/scenes/<cover>/tile-<seed>/noise-<mm>/{cands/, cands.mk, detections.json, .geojson}
#   out/scenes/<cover>/tile-<seed>/noise-<mm>/scored.png                  the tile from above
#   results/scenes/score.json, results/scenes/{summary,pr,models,cover_bins,matches}.csv
#   results/scenes/top-<cover>.png     per cover level: rows = noise, columns = the first
#                                      SCENE_PICTURE_SEEDS tiles, coloured by outcome
#   results/scenes/cover.png, noise.png   recall and recognition against cover and noise
# The report's "Scene experiment" section (results/report.md) renders score.json and the
# stages' .time files. Sizes and why: docs/decisions/scene-experiment.md ("Sizes").
#
# How it joins `all`: every tile's generated makefile (cands.mk) is an included makefile, which
# make brings up to date before any goal, so the scene rules are read only by a make whose goal
# is `scenes`; `all` runs that make as a recursive step (the rule of results/scenes/score.json
# below), so `make tools` never renders a tile. A dry run (-n, -q, -t) reads the generated plans
# as they are and never remakes them (read_plan), so `make -q all` and `make -q scenes` answer
# without rendering or detecting, and `make -n` prints the stages known so far (the candidates
# of a tile not yet detected are not known before its detect has run).
SCENE_SEEDS ?= 1 2 3 4 5 6 7 8
SCENE_COVERS ?= light medium dense
SCENE_NOISES ?= 0 8 32
# The recipe's variables (SCENE_EXTENT, SCENE_MODELS, the cover knobs, SCENE_SPACING, SCENE_SENSOR,
# SCENE_CLUTTER, SCENE_VEHICLES) and scene_recipe(cover, seed): mk/scene-recipe.mk.
include mk/scene-recipe.mk
# The pictures per cover level show the first SCENE_PICTURE_COLS tiles at every noise level.
SCENE_PICTURE_COLS ?= 4
SCENE_TOPVIEW_SIZE ?= 512
SCENE_DIR := $(OUT)/scenes
SCENE_RES := $(RES)/scenes
SCENE_SCORE := $(SCENE_RES)/score.json
# SCENE_TILE_DIR: where the tiles are rendered (recipe.scene, scan.pcd, truth.json, scan.traj), by
# default SCENE_DIR itself. Another make's SCENE_DIR shares its renders: the density ladder's
# detect ablations run their chain on the canopy rung's tiles (mk/density.mk; the same recipe and
# seed render the same bytes, so a render made here or there is the same file).
SCENE_TILE_DIR ?= $(SCENE_DIR)
SCENE_TILES := $(foreach c,$(SCENE_COVERS),$(foreach s,$(SCENE_SEEDS),$(SCENE_TILE_DIR)/$(c)/tile-$(s)))
SCENE_RUNS := $(foreach c,$(SCENE_COVERS),$(foreach s,$(SCENE_SEEDS),$(foreach n,$(SCENE_NOISES),$(SCENE_DIR)/$(c)/tile-$(s)/noise-$(n))))
# A dry run of a make that shares another's renders plans none of them: that make, run before it,
# plans them (the progress count, tests/pipeline/progress_count.sh). Run for real, it renders a
# shared tile only when the other's render is gone and this make needs it again (the density
# ladder's detect ablation with a changed detect file after the rung was scored): then the stage
# extends the count.
scene_shared_dry = $(and $(dry_run),$(filter-out $(SCENE_DIR),$(SCENE_TILE_DIR)))
# scene_tile_of(RUN): the tile directory a run's scan comes from.
scene_tile_of = $(patsubst $(SCENE_DIR)/%,$(SCENE_TILE_DIR)/%,$(patsubst %/,%,$(dir $(1))))
# (A make variable name: every / - . of the path becomes _; an OUT under mktemp has a dot.)
scene_key = S_$(subst .,_,$(subst -,_,$(subst /,_,$(1))))
# The PCL baseline beside canopy (issue 17; docs/decisions/baseline.md §4): each method of
# SCENE_BASELINE answers every candidate (`baseline --verdict METHOD` on the candidate's
# samples.pcd, the same modelbase: cands/<id>/baseline-<method>.json, a canopy.verdict), and
# the same collect and score turn the answers into <run>/detections-baseline-<method>.json and
# results/scenes/baseline-<method>/score.json (+ CSVs), which the report's scene section shows
# beside canopy's. SCENE_BASELINE= (empty) leaves the baseline out.
SCENE_BASELINE ?= vfh fpfh
$(if $(filter-out vfh fpfh,$(SCENE_BASELINE)),$(error SCENE_BASELINE=$(SCENE_BASELINE): methods are vfh and fpfh))
# FPFH poses scored by verify (issue 29, "what each stage adds"; docs/decisions/baseline.md §8,
# scene-experiment.md "What gmatch adds"): with fpfh in SCENE_BASELINE, its stage also writes its
# ranking of every model with each one's pose (`baseline --hypotheses`: cands/<id>/hypotheses-fpfh.json,
# no extra FPFH run), verify checks that list as it checks gmatch's (its parameters: top-k of FPFH's
# ranking, each from FPFH's pose and the principal axes; cands/<id>/verdict-fpfh.json), and collect
# and score make results/scenes/baseline-fpfh-verify/ (the report's row "FPFH poses, verify").
# SCENE_FPFH_VERIFY=0 leaves it out.
SCENE_FPFH_VERIFY ?= 1
$(if $(filter-out 0 1,$(SCENE_FPFH_VERIFY)),$(error SCENE_FPFH_VERIFY=$(SCENE_FPFH_VERIFY): must be 0 or 1))
scene_fpfh_verify = $(if $(filter fpfh,$(SCENE_BASELINE)),$(filter 1,$(SCENE_FPFH_VERIFY)))
# The size-only ablation (issue 29, "what each stage adds"; docs/decisions/scene-experiment.md):
# no model chain at all: each candidate classify answers with a class becomes a detection of
# the modelbase model nearest to classify's length, width and height (`collect --size-only`),
# scored like the baseline as results/scenes/baseline-size/. It reads only what canopy's runs
# already made (class.json, the surfaces): one collect per run and one score. SCENE_SIZE_ONLY=0
# leaves it out.
SCENE_SIZE_ONLY ?= 1
$(if $(filter-out 0 1,$(SCENE_SIZE_ONLY)),$(error SCENE_SIZE_ONLY=$(SCENE_SIZE_ONLY): must be 0 or 1))
# (the methods beside canopy: the report reads only theirs, report --tile-baselines)
scene_bl_methods := $(strip $(SCENE_BASELINE) $(if $(filter 1,$(SCENE_SIZE_ONLY)),size)$(if \
  $(scene_fpfh_verify), fpfh-verify))
SCENE_BL_SCORES := $(foreach m,$(scene_bl_methods),$(SCENE_RES)/baseline-$(m)/score.json)
SCENE_ABL_SCORE := $(foreach v,$(SCENE_CLASS_ABLATIONS),$(SCENE_RES)/$(v)/score.json) \
  $(foreach v,$(SCENE_COLLECT_VARIANTS),$(SCENE_RES)/$(v)/score.json) \
  $(if $(SCENE_VERIFY_ABLATION),$(SCENE_RES)/verify-ablation/score.json)
# The scene experiment's own classify ablations (issues 27 and 29; docs/decisions/scene-experiment.md,
# "Stop 56"): `all` runs the experiment's `make scenes` with SCENE_CLASSIFY_ABLATIONS =
# SCENES_CLASSIFY_ABLATION SCENES_CLASSIFY_ABLATION_2 (the hook above; an empty one "-"), so each
# default classify-sim.ini changed keeps its ablation in the report (report
# --tile-classify-ablation[-2], "classify's ablations on the scene experiment"): the roughness
# threshold's floor before docs/decisions/classify.md §28 (100mm) and the shoulder gate off (min-shoulder
# 0, before §30), the density ladder's two files (classify-sim.ini with that key changed alone,
# written by make: Makefile.experiments CLASSIFY_SIM_VARIANTS). Empty: none (SCENES_CLASSIFY_ABLATION=
# SCENES_CLASSIFY_ABLATION_2= plans no ablation stage). Two names, not a list: the report takes
# these two (--tile-classify-ablation[-2]) and names them. A `make scenes` of one's own takes
# SCENE_CLASSIFY_ABLATIONS as given (empty unless set), as the density ladder's and the open
# set's do.
SCENES_CLASSIFY_ABLATION ?= $(call classify_sim_variant,floor-100)
SCENES_CLASSIFY_ABLATION_2 ?= $(call classify_sim_variant,shoulder-0)
scenes_class_ini.class-ablation = $(SCENES_CLASSIFY_ABLATION)
scenes_class_ini.class-ablation-2 = $(SCENES_CLASSIFY_ABLATION_2)
SCENES_CLASS_ABLATIONS = $(foreach v,class-ablation class-ablation-2,$(if $(scenes_class_ini.$(v)),$(v)))
# The scene experiment's verify ablation (issue 29, "what each stage adds": what gmatch's ranking
# adds; docs/decisions/scene-experiment.md, "What gmatch adds"): `all` runs the experiment's `make
# scenes` with SCENE_VERIFY_ABLATION = SCENES_VERIFY_ABLATION, verify again on every model-level
# candidate with these options after its parameters. Since stop 65 verify's top-k is 5, every model
# of the thesis modelbase (verify takes at most the models ranked, so gmatch's ranking chooses
# nothing there; its segment pairs still give the start poses); --top-k=3, the default before
# (verify.md §21), is the ablation: verify on gmatch's top 3 only. The report shows it beside the
# baseline's methods (report --tile-verify-ablation). Empty: none.
SCENES_VERIFY_ABLATION ?= --top-k=3
# (the scene experiment's sub-make's arguments: its classify and verify ablations, empty or not)
scenes_args = SCENE_CLASSIFY_ABLATIONS='$(or $(SCENES_CLASSIFY_ABLATION),-) $(or $(SCENES_CLASSIFY_ABLATION_2),-)' \
  SCENE_VERIFY_ABLATION='$(SCENES_VERIFY_ABLATION)'
SCENES_VERIFY_ABL_SCORE = $(if $(SCENES_VERIFY_ABLATION),$(SCENE_RES)/verify-ablation/score.json)
SCENES_CLASS_ABL_SCORES = $(foreach v,$(SCENES_CLASS_ABLATIONS),$(SCENE_RES)/$(v)/score.json)

.PHONY: scenes
# The report's "Scene experiment" section: the score, and the stages' .time files found through
# the score's list of tiles. SCENE_EXPERIMENT=0 leaves the scene experiment out of `all` and
# of the report (the pipeline tests' small slices of the thesis graph, a thesis-only run).
SCENE_EXPERIMENT ?= 1
$(if $(filter-out 0 1,$(SCENE_EXPERIMENT)),$(error SCENE_EXPERIMENT=$(SCENE_EXPERIMENT): must be 0 or 1))
ifeq ($(SCENE_EXPERIMENT),1)
$(RES)/report.md: $(SCENE_SCORE) $(SCENE_BL_SCORES) $(if $(filter collect-ablation,$(SCENE_COLLECT_VARIANTS)),$(SCENE_RES)/collect-ablation/score.json) \
  $(SCENES_CLASS_ABL_SCORES) $(SCENES_VERIFY_ABL_SCORE)
# (each classify ablation's score and parameter file: --tile-classify-ablation[-2] and its -config)
REPORT_ARGS += --tile-score $(SCENE_SCORE) --tile-baselines=$(or $(subst $(space),$(comma),$(scene_bl_methods)),none)$(if $(filter collect-ablation,$(SCENE_COLLECT_VARIANTS)), --tile-collect-ablation \
  $(SCENE_RES)/collect-ablation/score.json)$(if $(SCENES_CLASS_ABLATIONS), $(foreach v,$(SCENES_CLASS_ABLATIONS),--tile-$(patsubst \
  class-%,classify-%,$(v)) $(SCENE_RES)/$(v)/score.json --tile-$(patsubst class-%,classify-%,$(v))-config \
  $(scenes_class_ini.$(v))))$(if $(SCENES_VERIFY_ABLATION), --tile-verify-ablation $(SCENES_VERIFY_ABL_SCORE) \
  --tile-verify-ablation-options='$(SCENES_VERIFY_ABLATION)')
$(foreach f,$(filter-out $(classify_sim_files),$(SCENES_CLASSIFY_ABLATION) $(SCENES_CLASSIFY_ABLATION_2)),$(if $(wildcard \
  $(f)),,$(error \
  SCENES_CLASSIFY_ABLATION[_2]: $(f) does not exist)))
endif
ifeq ($(filter scenes,$(MAKECMDGOALS)),)
# ---- read by every other make (all, report, tools, ...) ----------------------------------
# results/scenes/score.json stands for the whole scene experiment: its rule is the recursive
# `make scenes`, which redoes only what is out of date. Under -q the sub-make is asked first
# (`make -q scenes`, which renders nothing), so `make -q all` exits 0 exactly when the scene
# experiment is up to date too; otherwise the step always runs (FORCE) and make compares
# score.json's time afterwards, so an unchanged experiment does not remake the report.
ifneq ($(findstring q,$(make_letters))$(filter 0,$(SCENE_EXPERIMENT)),q)
scenes_force := FORCE
else
scenes_force := $(if $(shell $(MAKE) -q --no-print-directory -f $(firstword $(MAKEFILE_LIST)) scenes \
  $(MAKEOVERRIDES) $(scenes_args) >/dev/null 2>&1 || echo stale),FORCE)
endif
# What the sub-make shares with this make is built here first (the tools, the modelbase from
# the thesis trials), so the two never build one artifact at the same time.
SCENE_TOOLS := rangetrace addnoise detect classify fitvox cocone ncut gmatch verify collect score topview figures \
  $(if $(SCENE_BASELINE),baseline)
# (The baseline's models' side too, when SCENE_MB is the thesis modelbase, whose rule this make has.)
$(SCENE_SCORE): $(scenes_force) $(foreach t,$(SCENE_TOOLS),$(call tool,$(t))) $(MODELBASE) $(VERIFY_SURFACES) \
  $(if $(SCENE_BASELINE),$(filter $(call baseline_models,$(OUT)/modelbase),$(call baseline_models,$(SCENE_MB))))
	+@$(MAKE) --no-print-directory -f $(firstword $(MAKEFILE_LIST)) scenes PROGRESS=0 $(scenes_args)
# The baseline's scores and the ablations' are made by the same sub-make (no recipe of their own
# here).
$(SCENE_BL_SCORES) $(if $(filter collect-ablation,$(SCENE_COLLECT_VARIANTS)),$(SCENE_RES)/collect-ablation/score.json) $(SCENES_CLASS_ABL_SCORES) \
  $(SCENES_VERIFY_ABL_SCORE): $(SCENE_SCORE)
else
# ---- read only by `make scenes` ----------------------------------------------------------
SCENE_MB := $(OUT)/modelbase
TILE_CAND_KINDS += $(foreach m,$(SCENE_BASELINE),baseline:cand/baseline-$(m).json)
# The options files of the tile workflow's stages (above) and of the score and the pictures.
tile_classify := $(SCENE_CLASSIFY)
tile_detect := $(SCENE_DETECT)
opts_text_topview = $(call opts_line,size,$(SCENE_TOPVIEW_SIZE))
opts_text_score = $(call opts_line,model-classes,$(SCENE_MODEL_CLASSES))
$(call tile_opts_kinds,$(SCENE_DIR))
$(call opts_kinds,$(SCENE_DIR),score)
# Whether the fpfh stage writes FPFH's ranking and poses too (SCENE_FPFH_VERIFY): turned on over
# runs made without them, the stage runs again (its verdict alone would leave verify no poses).
opts_text_baseline-fpfh = $(call opts_line,hypotheses,$(scene_fpfh_verify))
$(if $(filter fpfh,$(SCENE_BASELINE)),$(call opts_kinds,$(SCENE_DIR),baseline-fpfh))

# The recipes and the score's manifests are written at parse time when they changed
# (text_prereq, Makefile.experiments).

# The recipe of one tile (cover, seed): scene_recipe (mk/scene-recipe.mk).
$(if $(dry_run),,$(shell mkdir -p $(SCENE_TILES) $(SCENE_RES) $(dir $(SCENE_BL_SCORES) $(SCENE_ABL_SCORE))))

# scene_tile_rule(cover, seed): the recipe and the render.
define scene_tile_rule
$(SCENE_TILE_DIR)/$(1)/tile-$(2)/recipe.scene: $(call text_prereq,$(SCENE_TILE_DIR)/$(1)/tile-$(2)/recipe.scene,$(call scene_recipe,$(1),$(2)))
$(SCENE_TILE_DIR)/$(1)/tile-$(2)/scan.pcd: $(SCENE_TILE_DIR)/$(1)/tile-$(2)/recipe.scene $(call tool,rangetrace)
	@$(if $(scene_shared_dry),: the render of $$@ is planned by its own make,$(STAGE) $$@ -- $(BIN)/rangetrace --scene $$< --seed \
	  $$(call seed,scenes/$(1)/$(2)) --threads 2 -o $$@ --truth $(SCENE_TILE_DIR)/$(1)/tile-$(2)/truth.json)
$(SCENE_TILE_DIR)/$(1)/tile-$(2)/truth.json: $(SCENE_TILE_DIR)/$(1)/tile-$(2)/scan.pcd
$(if $(SCENE_SENSOR),$(SCENE_TILE_DIR)/$(1)/tile-$(2)/scan.traj: $(SCENE_TILE_DIR)/$(1)/tile-$(2)/scan.pcd)
endef

# scene_noise_rule(cover, seed, noise): the noisy scan.
define scene_noise_rule
$(call noisy_rule,$(SCENE_TILE_DIR)/$(1)/tile-$(2)/scan.pcd,$(SCENE_DIR)/$(1)/tile-$(2)/noise-$(3)/scan.pcd,$(3),scenes/$(1)/$(2)/$(3))
endef

$(foreach c,$(SCENE_COVERS),$(foreach s,$(SCENE_SEEDS),$(eval $(call scene_tile_rule,$(c),$(s)))))
$(foreach c,$(SCENE_COVERS),$(foreach s,$(SCENE_SEEDS),$(foreach n,$(SCENE_NOISES),$(eval $(call scene_noise_rule,$(c),$(s),$(n))))))
# detect writes no classes.ply for the experiment's runs (nothing reads it; KEEP=1 keeps it).
# With a sensor, detect takes the directions toward the sensor from the tile's trajectory.
scene_traj = $(call scene_tile_of,$(1))/scan.traj
$(foreach r,$(SCENE_RUNS),$(eval $(call tile_rules,$(call scene_key,$(r)),$(r),$(r)/scan.pcd,$(SCENE_MB),$(if $(keep),,--no-classes)$(if \
  $(SCENE_SENSOR), --trajectory $(call scene_traj,$(r))))))
$(if $(SCENE_SENSOR),$(foreach r,$(SCENE_RUNS),$(eval $(r)/cands/index.json: $(call scene_traj,$(r)))))
$(foreach r,$(SCENE_RUNS),$(call read_plan,$(r)/cands.mk))
# ncut's seed key is the run's place under scenes/ (scenes/<cover>/tile-<seed>/noise-<mm>/<id>),
# never a path with $(OUT) in it: the same experiment in another directory gives the same bytes.
$(foreach r,$(SCENE_RUNS),$(call cand_rules,$(r),$(call scene_key,$(r)),$(SCENE_MB),$(patsubst $(SCENE_DIR)/%,scenes/%,$(r)),$(SCENE_CLASSIFY)))
$(foreach r,$(SCENE_RUNS),$(eval $(call tile_collect,$(call scene_key,$(r)),$(r),$(SCENE_MB),$(r)/scan.pcd)))
# The experiment's modelbase is built here (graphs; surfaces when mk/verify.mk is read). classify
# reads its entries' classes too (class_rule lists them by $(wildcard), which is empty before
# they exist: a `make scenes` on a fresh OUT classified without them, s53), so with the thesis
# modelbase every candidate's class.json waits for its graphs and surfaces.
$(foreach r,$(SCENE_RUNS),$(foreach c,$(call model_cands,$(call scene_key,$(r))),\
  $(eval $(r)/cands/$(c)/match.json $(r)/cands/$(c)/verdict.json: $(MODELBASE) $(VERIFY_SURFACES))))
$(if $(filter $(OUT)/modelbase,$(SCENE_MB)),$(foreach r,$(SCENE_RUNS),$(foreach c,$($(call scene_key,$(r))_CANDS),\
  $(eval $(r)/cands/$(c)/class.json$(foreach v,$(SCENE_CLASS_ABLATIONS), $(r)/cands/$(c)/$(v).json): $(MODELBASE) \
  $(VERIFY_SURFACES)))))
# The score's tile list (documents/tile_list.h): detections truth noise cover, one line per run
# (cover, seed, noise: the order of SCENE_RUNS), from the cover levels themselves.
scene_line = $(SCENE_DIR)/$(1)/tile-$(2)/noise-$(3)/detections.json $(SCENE_TILE_DIR)/$(1)/tile-$(2)/truth.json $(3) $(1)
scene_manifest = $(subst $(nl)$(space),$(nl),$(foreach c,$(SCENE_COVERS),$(foreach s,$(SCENE_SEEDS),$(foreach \
  n,$(SCENE_NOISES),$(call ml,$(call scene_line,$(c),$(s),$(n)))))))
$(SCENE_DIR)/tiles.txt: $(call text_prereq,$(SCENE_DIR)/tiles.txt,$(scene_manifest))
# The thesis models' classes (share/models/classes.csv) judge class answers on them (score
# --model-classes; a rendered "semi" answered "semi-tractor" is right at the class level). A
# prerequisite only when it exists: the open set's (mk/openset.mk) is written by the parent make,
# which a dry run does not do, and score names a missing file itself.
SCENE_MODEL_CLASSES ?= share/models/classes.csv
$(SCENE_SCORE): $(SCENE_DIR)/tiles.txt $(addsuffix /detections.json,$(SCENE_RUNS)) $(call tool,score) $(wildcard $(SCENE_MODEL_CLASSES)) \
    $(opts.score)
	@$(STAGE) $@ -- $(BIN)/score --tiles $(SCENE_DIR)/tiles.txt --model-classes $(SCENE_MODEL_CLASSES) -o $@ \
	  --csv $(SCENE_RES)/$(scene_scan_prune)
# The baseline (SCENE_BASELINE): per candidate and method a verdict from the candidate's
# samples (a failed fitvox leaves an empty samples.pcd, so the baseline fails too and collect
# counts the candidate as failed, as for canopy), per run collect, then one score per method
# over a manifest of the same tiles.
# (With SCENE_FPFH_VERIFY the fpfh stage writes hypotheses-fpfh.json too. It is not a target of
# its own: make 4.3's grouped targets break `make -n` planning (a dry run after the stage's
# prerequisites changed plans the readers of one target only: no verify-fpfh, so the progress
# count misses them; as ncut's segments.ply, Makefile.experiments), so its reader depends on
# baseline-fpfh.json, and SCENE_FPFH_VERIFY is the stage's option (opts.baseline-fpfh). The old
# file goes first: a failed stage (--record-failure: an empty baseline-fpfh.json) leaves none, and
# verify then fails on it as the candidate's chain failed, never reading the poses of an earlier
# run.)
scene_bl_hyp = $(if $(filter fpfh,$(3)),$(if $(scene_fpfh_verify),$(1)/cands/$(2)/hypotheses-fpfh.json))
define scene_baseline_cand_rule
$(1)/cands/$(2)/baseline-$(3).json: $(1)/cands/$(2)/samples.pcd $(VERIFY_SURFACES) \
    $(call baseline_models,$(SCENE_MB)) $(call tool,baseline) $(P)/baseline.ini $(opts.params)$(if \
    $(filter fpfh,$(3)), $(opts.baseline-fpfh))
	$(if $(filter fpfh,$(3)),@rm -f $(1)/cands/$(2)/hypotheses-fpfh.json)
	@$(STAGE) --record-failure $$@ -- $(BIN)/baseline --config $(P)/baseline.ini \
	  --verdict $(3) -i $(1)/cands/$(2)/samples.pcd --modelbase $(SCENE_MB) --model-cache $(call \
	  baseline_models,$(SCENE_MB)) -o $$@$(if $(scene_bl_hyp), --hypotheses $(scene_bl_hyp))
endef
# The models' side of another SCENE_MB than the thesis modelbase's (mk/baseline.mk).
$(if $(SCENE_BASELINE),$(if $(filter-out $(OUT)/modelbase,$(SCENE_MB)),$(eval $(call baseline_models_rule,$(SCENE_MB),$(VERIFY_SURFACES)))))
# scene_variant_score_rule(VARIANT): the score of every run's detections-VARIANT.json
# (baseline-<method>, baseline-size, class-ablation[-2], ...) as $(SCENE_RES)/VARIANT/score.json.
scene_variant_score_rule = $(call variant_score_rule,$(1),$(SCENE_DIR),$(scene_manifest),$(SCENE_RUNS),$(SCENE_RES),$(SCENE_MODEL_CLASSES))
$(foreach m,$(SCENE_BASELINE),$(foreach r,$(SCENE_RUNS),$(foreach c,$(call model_cands,$(call scene_key,$(r))),\
  $(eval $(call scene_baseline_cand_rule,$(r),$(c),$(m))))))
# (--refused-below=0: the 0.8 of collect's --refused-below is read on verify's calibrated
# confidence, verify.md §15; a baseline's confidence is its method's score, which that bound does
# not mean anything for, so its model answers are not set aside: open-set.md "Seventh round".)
$(foreach m,$(SCENE_BASELINE),$(foreach r,$(SCENE_RUNS),$(eval $(call collect_variant_rule,$(r),$(call scene_key,$(r)),$(SCENE_MB),\
  baseline-$(m),class.json,baseline-$(m).json,--verdict-name baseline-$(m).json --refused-below=0))))
$(foreach m,$(SCENE_BASELINE),$(eval $(call scene_variant_score_rule,baseline-$(m))))
# FPFH poses scored by verify (SCENE_FPFH_VERIFY): per model-level candidate (verify_rule on the
# fpfh stage's hypotheses-fpfh.json into cands/<id>/verdict-fpfh.json), per run, one score.
ifneq ($(scene_fpfh_verify),)
TILE_CAND_KINDS += verify:cand/verdict-fpfh.json
$(foreach r,$(SCENE_RUNS),$(foreach c,$(call model_cands,$(call scene_key,$(r))),\
  $(eval $(call verify_rule,$(r),$(c),$(call scene_key,$(r)),$(SCENE_MB),verdict-fpfh.json,,fpfh))))
$(foreach r,$(SCENE_RUNS),$(eval $(call collect_variant_rule,$(r),$(call scene_key,$(r)),$(SCENE_MB),\
  baseline-fpfh-verify,class.json,verdict-fpfh.json,--verdict-name verdict-fpfh.json$(collect_calibration),,\
  $(COLLECT_CALIBRATION) $(opts.collect))))
$(eval $(call scene_variant_score_rule,baseline-fpfh-verify))
endif
# The size-only ablation: per run, collect from classify's measurements alone; scored as above.
# (The surfaces as $(wildcard): the parent make builds them before this sub-make, and a dry run
# of it must not plan their thesis stages a second time: the progress count.)
ifeq ($(SCENE_SIZE_ONLY),1)
$(foreach r,$(SCENE_RUNS),$(eval $(call collect_variant_rule,$(r),$(call scene_key,$(r)),$(SCENE_MB),baseline-size,\
  class.json,,--size-only,,$(wildcard $(VERIFY_SURFACES)))))
$(eval $(call scene_variant_score_rule,baseline-size))
endif
# classify's ablations (SCENE_CLASSIFY_ABLATIONS): per run, then one score each.
TILE_CAND_KINDS += $(foreach v,$(SCENE_CLASS_ABLATIONS),classify:cand/$(v).json)
$(call class_ablations,$(SCENE_RUNS),$(SCENE_MB),$(SCENE_DIR),$(scene_manifest),$(SCENE_RES),$(SCENE_MODEL_CLASSES))
# collect's ablations (SCENE_COLLECT_ABLATIONS): per run, then one score each.
$(call collect_ablations,$(SCENE_RUNS),$(SCENE_MB),$(SCENE_DIR),$(scene_manifest),$(SCENE_RES),$(SCENE_MODEL_CLASSES))
# verify's ablation (SCENE_VERIFY_ABLATION): per model-level candidate and run, then one score.
ifneq ($(SCENE_VERIFY_ABLATION),)
TILE_CAND_KINDS += verify:cand/verdict-ablation.json
$(foreach r,$(SCENE_RUNS),$(call verify_ablation_rules,$(r),$(call scene_key,$(r)),$(SCENE_MB),$(SCENE_VERIFY_ABLATION)))
$(foreach r,$(SCENE_RUNS),$(foreach c,$(call model_cands,$(call scene_key,$(r))),\
  $(eval $(r)/cands/$(c)/verdict-ablation.json: $(MODELBASE) $(VERIFY_SURFACES))))
$(eval $(call scene_variant_score_rule,verify-ablation))
endif
# Per run: the tile from above with truth and detections coloured by the score's outcome
# (right green, wrong model orange, false alarm magenta, missed yellow, found truth white).
# It is the last reader of the run's scan and of the tile's render (all noisy scans exist once
# the score does): both are deleted after it unless KEEP=1 (.SECONDARY: not remade while what
# was made from them is current).
define scene_picture_rule
$(1)/scored.png: $(SCENE_SCORE) $(1)/scan.pcd $(call tool,topview) $(opts.topview)
	@$(STAGE) $$@ -- $(BIN)/topview -i $(1)/scan.pcd --detections $(1)/detections.json --size $(SCENE_TOPVIEW_SIZE) \
	  --truth $(call scene_tile_of,$(1))/truth.json --score $(SCENE_SCORE) -o $$@$(call scene_prune,$(1))
endef
scene_prune = $(if $(keep),, && rm -f $(1)/scan.pcd $(call scene_tile_of,$(1))/scan.pcd)
.SECONDARY: $(addsuffix /scan.pcd,$(SCENE_TILES) $(SCENE_RUNS))
# (topview finds the run's tile in the score by its detections path, as tiles.txt gives it)
$(foreach r,$(SCENE_RUNS),$(eval $(call scene_picture_rule,$(r))))
# Per cover level: one grid, rows = noise levels, columns = the first tiles.
SCENE_PICTURE_SEEDS := $(wordlist 1,$(SCENE_PICTURE_COLS),$(SCENE_SEEDS))
define scene_grid_rule
$(SCENE_RES)/top-$(1).png: $(foreach n,$(SCENE_NOISES),$(foreach s,$(SCENE_PICTURE_SEEDS),$(SCENE_DIR)/$(1)/tile-$(s)/noise-$(n)/scored.png)) $(call tool,figures)
	@$(STAGE) $$@ -- $(XRUN) $(BIN)/figures grid -o $$@ --cols $(words $(SCENE_PICTURE_SEEDS)) --no-trim \
	  --title "$(1) cover: right model green, wrong model orange, false alarm magenta, missed yellow" \
	  --labels-row "$(foreach n,$(SCENE_NOISES),$(n)mm)" --labels-col "$(foreach s,$(SCENE_PICTURE_SEEDS),tile-$(s))" \
	  $(foreach n,$(SCENE_NOISES),$(foreach s,$(SCENE_PICTURE_SEEDS),$(SCENE_DIR)/$(1)/tile-$(s)/noise-$(n)/scored.png))
endef
$(foreach c,$(SCENE_COVERS),$(eval $(call scene_grid_rule,$(c))))
# Recall and recognition against the measured per-vehicle cover (one line per noise level) and
# against noise (one line per cover level), from the score's tables.
$(SCENE_RES)/cover.png: $(SCENE_SCORE) $(call tool,figures)
	@$(STAGE) $@ -- $(XRUN) $(BIN)/figures plot -i $(SCENE_RES)/cover_bins.csv --x cover_lo --y recognition \
	  --series noise_mm --panel "" --xlabel "canopy cover over the vehicle (bin from)" \
	  --ylabel "recognition (right model within 1.5 m)" --title "recognition against canopy cover, one line per noise (mm)" -o $@
$(SCENE_RES)/noise.png: $(SCENE_SCORE) $(call tool,figures)
	@$(STAGE) $@ -- $(XRUN) $(BIN)/figures plot -i $(SCENE_RES)/summary.csv --x noise_mm --y recognition \
	  --series cover --panel "" --xlabel "noise (mm)" \
	  --ylabel "recognition (right model within 1.5 m)" --title "recognition against noise, one line per cover level" -o $@
# SCENE_PICTURES=0: the scores only (the density ladder and the open set, mk/density.mk,
# mk/openset.mk). Then detect is the scans' last reader, and they are deleted once the score is
# made, unless KEEP=1 (.SECONDARY above: not remade while what was made from them is current).
# SCENE_KEEP_TILE_SCANS=1 keeps the tiles' renders (the runs' scans still go): another make reads
# them after this one (SCENE_TILE_DIR; the density ladder's detect ablations) and deletes them.
SCENE_PICTURES ?= 1
SCENE_KEEP_TILE_SCANS ?= 0
scene_scan_prune = $(if $(or $(keep),$(filter-out 0,$(SCENE_PICTURES))),, && rm -f $(addsuffix /scan.pcd,$(if \
  $(filter 1,$(SCENE_KEEP_TILE_SCANS)),,$(SCENE_TILES)) $(SCENE_RUNS)))
scenes: $(SCENE_SCORE) $(SCENE_BL_SCORES) $(SCENE_ABL_SCORE) $(if $(filter 1,$(SCENE_PICTURES)),$(addsuffix /scored.png,$(SCENE_RUNS)) \
    $(foreach c,$(SCENE_COVERS),$(SCENE_RES)/top-$(c).png) $(SCENE_RES)/cover.png $(SCENE_RES)/noise.png)
endif
