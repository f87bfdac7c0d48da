# The PCL baseline beside canopy (issue 17; docs/decisions/baseline.md), included by
# Makefile.experiments.
#   make -f Makefile.experiments baselines             baseline.json beside every match.json
#   make -f Makefile.experiments all                   ... and the report shows them
# BASELINE=1 (default) makes the report depend on every trial's baseline.json, so `all` runs
# the baseline too (90 trials ≈ 50-64 CPU-seconds); BASELINE=0 leaves it out of `all` (the
# report then shows a baseline section only for trials that already have a baseline.json; the
# pipeline tests' one-trial slices use it).
# Per trial: out/<object>/<scene>/noise-<mm>/baseline.json from the trial's samples.pcd and the
# modelbase surfaces (<model>.pcd, mk/verify.mk), with its wall time and peak memory in
# baseline.json.time. The report reads them (tools/report/baseline_section.h) into a section of
# report.md and results/baseline.csv (rank-1 per trial of both methods beside gmatch's, time).
# The scene experiment runs the baseline on every tile candidate too (`baseline --verdict`,
# scored by collect + score beside canopy): mk/scenes.mk, SCENE_BASELINE.
# The tool's build rule and content stamp (not in TOOLS, so `make tools` stays as it was):
$(eval $(call tool_rule,baseline))

# The models' side of the baseline (docs/decisions/baseline.md §7, cost.md §12): the same for
# every candidate, so computed once per modelbase (`baseline --prepare`) into
# <modelbase>/baseline-models.bin (canopy.baseline-models, formats/README.md), which every
# baseline run of that modelbase reads (--model-cache; same bytes as computing it). Remade when
# a surface, the tool or baseline.ini changes; a run refuses a file made from other surfaces or
# parameters. baseline_models_rule(modelbase dir, its surfaces) (scenes.mk, families.mk).
baseline_models = $(1)/baseline-models.bin
define baseline_models_rule
$(call baseline_models,$(1)): $(sort $(2) $(wildcard $(1)/*.pcd)) $(call tool,baseline) $(P)/baseline.ini $(opts.params)
	@$(STAGE) $$@ -- $(BIN)/baseline --config $(P)/baseline.ini --prepare --modelbase $(1) -o $$@
endef
$(eval $(call baseline_models_rule,$(OUT)/modelbase,$(VERIFY_SURFACES)))

define baseline_rule
$(OUT)/$(1)/$(2)/noise-$(3)/baseline.json: $(OUT)/$(1)/$(2)/noise-$(3)/samples.pcd $(VERIFY_SURFACES) \
    $(call baseline_models,$(OUT)/modelbase) $(call tool,baseline) $(P)/baseline.ini $(opts.params)
	@$(STAGE) --record-failure $$@ -- $(BIN)/baseline --config $(P)/baseline.ini -i $$< \
	  --modelbase $(OUT)/modelbase --model-cache $(call baseline_models,$(OUT)/modelbase) -o $$@
endef
$(foreach o,$(OBJECTS),$(foreach s,$(SCENES),$(foreach n,$(NOISES),$(eval $(call baseline_rule,$(o),$(s),$(n))))))
BASELINES := $(addsuffix /baseline.json,$(CASES))
.PHONY: baselines
baselines: $(BASELINES)
# The report shows them beside canopy and writes results/baseline.csv.
BASELINE ?= 1
ifeq ($(BASELINE),1)
$(RES)/report.md: $(BASELINES)
$(RES)/baseline.csv: $(RES)/report.md
endif
