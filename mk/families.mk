# Vehicle families, class-level protocol (issue 17; docs/decisions/families.md), included by
# Makefile.experiments. Part of `all` at a default size that fits its time budget (FAMILIES=1);
# FAMILIES=0 leaves it out of `all` and of the report.
#
#   make -f Makefile.experiments families -j2 [FAM_CLASSES="pickup van" FAM_TRAIN="0 1"
#        FAM_TEST="1000" FAM_COVERS=light FAM_NOISES=0]
#   make -f Makefile.experiments families -j2 FAM_TEST="1000 1001" FAM_NOISES="0 8 32"
#        ... the full size (216 trials; ≈ 4 times the default's cost)
#   make -f Makefile.experiments families results/report.md -j2   ... and the report with its
#        "Vehicle families" section
#   make -f Makefile.experiments family-modelbase FAM_MB_N=1000 -j2
#        a modelbase of FAM_MB_N generated instances spread over the classes (not in `all`):
#        out/families/modelbase-<N>/<class>-<n>.{json,pcd,class}
#
# Modelbase: instances FAM_TRAIN of every class in FAM_CLASSES (procedural, rangetrace --model
# family:<class>:<n>), rendered with the modelbase's `unoccluded` views and taken through the
# same stages as verify-modelbase (addnoise 0 mm, fitvox, cocone, ncut):
#   out/families/train/<class>-<n>/{noise-0/samples.pcd, mesh.ply, segments.json}
#   out/families/modelbase/<class>-<n>.{json,pcd,class}
# The two scans of an entry (scan.pcd and noise-0/scan.pcd, 15-20 MB each) are deleted once the
# next stage has read them (.SECONDARY: make does not remake them while what was made from them
# is up to date); their .log and .time stay. Likewise a trial's noise-<mm>/scan.pcd.
# Tests: OTHER instances (FAM_TEST, disjoint from FAM_TRAIN) at a random heading from the seed,
# under foliage of each cover level, with each noise level, through
# addnoise | fitvox | cocone | ncut | gmatch | verify -k FAM_TOPK, and the PCL baseline
# (tools/baseline, one process per method) on the same samples.pcd and the same modelbase:
#   out/families/test/<class>-<n>/<cover>/scan.pcd                rendered once per cover
#   out/families/test/<class>-<n>/<cover>/noise-<mm>/{samples.pcd, mesh.ply, segments.json,
#                          match.json, verdict.json, baseline-vfh.json, baseline-fpfh.json}
#   results/families/{confusion.csv, accuracy.csv}     famscore: verify's class answers
#   results/families/{methods.csv, methods-confusion.csv}
#                                                      gmatch rank-1, verify, VFH, FPFH side by side
# A stage failing on its input (e.g. cocone on a candidate that foliage left in pieces) is
# recorded (stage.sh --record-failure): the trial's verdict is empty and counts as class none.
FAMILIES ?= 1
$(if $(filter-out 0 1,$(FAMILIES)),$(error FAMILIES=$(FAMILIES): must be 0 or 1))
FAM_CLASSES ?= sedan hatchback suv pickup van box-truck semi-tractor bus wheeled-apc tracked-apc \
  tank wheel-loader
FAM_TRAIN ?= 0 1 2
# The default size runs inside `all` (docs/decisions/families.md §9: measured stage costs):
# one test instance per class, the extreme noise levels. The full size: FAM_TEST="1000 1001"
# FAM_NOISES="0 8 32".
FAM_TEST ?= 1000
# Cover levels (the scene experiment's names): foliage discs over the vehicle's square.
FAM_COVERS ?= light medium dense
FAM_FOLIAGE_light ?= 250
FAM_FOLIAGE_medium ?= 500
FAM_FOLIAGE_dense ?= 800
FAM_NOISES ?= 0 32
FAM_VIEWS ?= circle 12 75deg
FAM_TOPK ?= 5
# Image and crop box large enough for a 13.5 m bus and a 4 m semi-tractor (the thesis's 10 x 4
# x 4 m box would cut them); the thesis's 30 mm pixel spacing, which fitvox is tuned to.
FAM_RENDER ?= --size 640 --spacing 30mm --crop-length 15m --crop-width 5m --crop-height 4.6m
# family-modelbase: entry i (0 .. N-1) is instance i div K of class i mod K (K classes).
FAM_MB_N ?= 1000
# ... and entry i's render waits for entry i - FAM_MB_WINDOW to be done (an order-only
# prerequisite), so at most FAM_MB_WINDOW entries are under way and their 15-20 MB scans on
# disk at once; without it make -j renders all N first (N x 17 MB). Keep it >= the -j count;
# 0 = no window (e.g. LAUNCH=slurm with hundreds of jobs and the disk to hold every scan).
FAM_MB_WINDOW ?= 16
FAM_DIR := $(OUT)/families
FAM_MB := $(FAM_DIR)/modelbase
FAM_RES := $(RES)/families
FAM_TABLES := $(FAM_RES)/confusion.csv $(FAM_RES)/accuracy.csv $(FAM_RES)/methods.csv \
  $(FAM_RES)/methods-confusion.csv
# The tools of the protocol; famscore links the family generator from the simulator's library (sim/).
FAM_TOOLS := rangetrace addnoise fitvox cocone ncut gmatch verify baseline famscore
$(if $(filter famscore,$(TOOLS)),,$(eval $(call tool_rule,famscore)))

.PHONY: families family-modelbase
ifneq ($(filter families family-modelbase,$(MAKECMDGOALS)),)
$(if $(filter $(FAM_TRAIN),$(FAM_TEST)),$(error families: FAM_TEST and FAM_TRAIN share instances \
  ($(filter $(FAM_TRAIN),$(FAM_TEST))); the tests must be other instances))
$(foreach c,$(FAM_COVERS),$(if $(FAM_FOLIAGE_$(c)),,$(error families: no FAM_FOLIAGE_$(c) for cover $(c))))
fam_heading = $(shell echo $$(( $(call seed,families/heading/$(1)) % 360 )))deg

# The test scenes and the runs manifest are written at parse time when they changed
# (text_prereq, Makefile.experiments).
$(if $(dry_run),,$(shell mkdir -p $(FAM_DIR)/scenes))
# The renders' options (FAM_RENDER) and verify's (FAM_TOPK), as prerequisites (the options files,
# Makefile.experiments; the parameters' directory P is the thesis graph's opts.params).
opts_text_families-render = $(call opts_line,render,$(FAM_RENDER))
opts_text_families-verify = $(call opts_line,top-k,$(FAM_TOPK))
$(call opts_kinds,$(OUT),families-render families-verify)

# The test scenes: one recipe per cover level.
define fam_scene_text
# families protocol (mk/families.mk): cover $(1)
foliage_count = $(FAM_FOLIAGE_$(1))
foliage_radius = 100mm
foliage_band = 2m
foliage_square = 16m
views = $(FAM_VIEWS)
endef
define fam_scene_rule
$(FAM_DIR)/scenes/$(1).scene: $(call text_prereq,$(FAM_DIR)/scenes/$(1).scene,$(call fam_scene_text,$(1)))
endef

# fam_chain(DIR, NOISE, SEEDKEY, FAIL, DROP): addnoise -> fitvox -> cocone -> ncut on DIR/scan.pcd.
# DROP non-empty: addnoise deletes DIR/scan.pcd after reading it. fitvox always deletes the noisy
# scan it read. Both are .SECONDARY: missing, they are not remade while their products are current.
define fam_chain
.SECONDARY: $(1)/noise-$(2)/scan.pcd $(if $(5),$(1)/scan.pcd)
$(call noisy_rule,$(1)/scan.pcd,$(1)/noise-$(2)/scan.pcd,$(2),$(3)/$(2),$(4),$(if $(5), && rm -f $$<))
$(1)/noise-$(2)/samples.pcd: $(1)/noise-$(2)/scan.pcd $(call tool,fitvox) $(P)/fitvox.ini $(opts.params)
	@$(STAGE) $(4) $$@ -- $(BIN)/fitvox --config $(P)/fitvox.ini --pcd-encoding $(PCD_ENCODING) -i $$< -o $$@ && rm -f $$<
$(1)/noise-$(2)/mesh.ply: $(1)/noise-$(2)/samples.pcd $(call tool,cocone) $(P)/cocone.ini $(opts.params)
	@$(STAGE) $(4) $$@ -- $(BIN)/cocone --config $(P)/cocone.ini -i $$< -o $$@
$(1)/noise-$(2)/segments.json: $(1)/noise-$(2)/mesh.ply $(call tool,ncut) $(P)/ncut.ini $(opts.params)
	@$(STAGE) $(4) $$@ -- $(BIN)/ncut --config $(P)/ncut.ini --seed $$(call seed,$(3)/$(2)) -i $$< \
	  -o $$@ --colored $(1)/noise-$(2)/segments.ply
endef

# fam_train_rule(class, n): the render and chain of one generated instance.
define fam_train_rule
$(FAM_DIR)/train/$(1)-$(2)/scan.pcd: $(call tool,rangetrace) $(P)/rangetrace.ini share/scenes/unoccluded.scene \
    $(opts.params) $(opts.families-render)
	@$(STAGE) $$@ -- $(BIN)/rangetrace --config $(P)/rangetrace.ini $(FAM_RENDER) --model family:$(1):$(2) \
	  --scene unoccluded --seed $$(call seed,families/train/$(1)-$(2)) --threads 2 -o $$@
$(call fam_chain,$(FAM_DIR)/train/$(1)-$(2),0,families/train/$(1)-$(2),,drop)
endef
# fam_entry_rule(modelbase dir, class, n): its modelbase entry (hard links to the train
# artifacts where the filesystem allows, else copies; the tools replace files by renaming, so a
# link keeps the entry's bytes as a copy would).
fam_link = ln -f $(1) $(2) 2>/dev/null || cp $(1) $(2)
define fam_entry_rule
$(1)/$(2)-$(3).json: $(FAM_DIR)/train/$(2)-$(3)/noise-0/segments.json
	@mkdir -p $$(@D) && $(call fam_link,$$<,$$(@D)/.$(2)-$(3).tmp$$$$$$$$.json) && \
	  mv $$(@D)/.$(2)-$(3).tmp$$$$$$$$.json $$@ && echo "done  $$@"
$(1)/$(2)-$(3).pcd: $(FAM_DIR)/train/$(2)-$(3)/noise-0/samples.pcd
	@mkdir -p $$(@D) && $(call fam_link,$$<,$$(@D)/.$(2)-$(3).tmp$$$$$$$$.pcd) && \
	  mv $$(@D)/.$(2)-$(3).tmp$$$$$$$$.pcd $$@ && echo "done  $$@"
$(1)/$(2)-$(3).class:
	@mkdir -p $$(@D) && echo $(2) >$$(@D)/.$(2)-$(3).tmp$$$$$$$$ && mv $$(@D)/.$(2)-$(3).tmp$$$$$$$$ $$@ && echo "done  $$@"
endef

FAM_ENTRIES := $(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TRAIN),$(FAM_MB)/$(c)-$(n)))
FAM_MODELBASE := $(foreach e,$(FAM_ENTRIES),$(e).json $(e).pcd $(e).class)
# The generated modelbase of FAM_MB_N entries (<class>:<n> words).
FAM_BIG := $(FAM_DIR)/modelbase-$(FAM_MB_N)
FAM_BIG_IDS := $(if $(filter family-modelbase,$(MAKECMDGOALS)),$(shell awk -v n='$(FAM_MB_N)' \
  -v cls='$(FAM_CLASSES)' 'BEGIN { k = split(cls, c, " "); for (i = 0; i < n; i++) print c[i % k + 1] ":" int(i / k) }'))
$(if $(filter family-modelbase,$(MAKECMDGOALS)),$(if $(FAM_BIG_IDS),,$(error family-modelbase: \
  FAM_MB_N=$(FAM_MB_N) gives no entry (a whole number >= 1))))
FAM_BIG_MODELBASE := $(foreach i,$(FAM_BIG_IDS),$(foreach e,$(FAM_BIG)/$(subst :,-,$(i)),$(e).json $(e).pcd $(e).class))
$(if $(FAM_BIG_IDS),$(if $(shell echo '$(FAM_MB_WINDOW)' | grep -Ex '[0-9]+'),,$(error \
  FAM_MB_WINDOW=$(FAM_MB_WINDOW): must be a whole number >= 0)))
# The window: "<entry>:<entry it waits for>" words, entry i after entry i - FAM_MB_WINDOW.
FAM_BIG_WAITS := $(if $(filter-out 0,$(FAM_MB_WINDOW)),$(shell printf '%s\n' $(subst :,-,$(FAM_BIG_IDS)) | \
  awk -v w='$(FAM_MB_WINDOW)' '{ id[NR] = $$0 } NR > w { print $$0 ":" id[NR - w] }'))
# Every instance rendered for a modelbase, once.
FAM_TRAIN_IDS := $(sort $(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TRAIN),$(c):$(n))) $(FAM_BIG_IDS))
fam_class = $(firstword $(subst :, ,$(1)))
fam_inst = $(lastword $(subst :, ,$(1)))

# fam_test_rule(class, n, cover): the render; fam_trial_rule(class, n, cover, noise): the trial.
define fam_test_rule
$(FAM_DIR)/test/$(1)-$(2)/$(3)/scan.pcd: $(FAM_DIR)/scenes/$(3).scene $(call tool,rangetrace) $(P)/rangetrace.ini \
    $(opts.params) $(opts.families-render)
	@$(STAGE) $$@ -- $(BIN)/rangetrace --config $(P)/rangetrace.ini $(FAM_RENDER) --model family:$(1):$(2) \
	  --scene $$< --heading $$(call fam_heading,$(1)-$(2)/$(3)) --seed $$(call seed,families/test/$(1)-$(2)/$(3)) \
	  --threads 2 -o $$@
endef
# fam_baseline_rule(trial dir, method): the PCL baseline, one process per method (its own time).
define fam_baseline_rule
$(1)/baseline-$(2).json: $(1)/samples.pcd $(FAM_MODELBASE) $(call baseline_models,$(FAM_MB)) $(call tool,baseline) \
    $(P)/baseline.ini $(opts.params)
	@$(STAGE) --record-failure $$@ -- $(BIN)/baseline --config $(P)/baseline.ini --methods $(2) -i $$< \
	  --modelbase $(FAM_MB) --model-cache $(call baseline_models,$(FAM_MB)) -o $$@
endef
define fam_trial_rule
$(call fam_chain,$(FAM_DIR)/test/$(1)-$(2)/$(3),$(4),families/test/$(1)-$(2)/$(3),--record-failure,)
$(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/match.json: $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/segments.json \
    $(FAM_MODELBASE) $(call tool,gmatch) $(P)/gmatch.ini $(opts.params)
	@$(STAGE) --record-failure $$@ -- $(BIN)/gmatch --config $(P)/gmatch.ini -i $$< --modelbase $(FAM_MB) -o $$@
$(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/verdict.json: $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/match.json \
    $(FAM_MODELBASE) $(call tool,verify) $(P)/verify.ini $(opts.params) $(opts.families-verify)
	@$(STAGE) --record-failure $$@ -- $(BIN)/verify --config $(P)/verify.ini -k $(FAM_TOPK) -i $$< \
	  --points $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/samples.pcd \
	  --segments $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/segments.json --modelbase $(FAM_MB) -o $$@
$(call fam_baseline_rule,$(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4),vfh)
$(call fam_baseline_rule,$(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4),fpfh)
endef

$(foreach c,$(FAM_COVERS),$(eval $(call fam_scene_rule,$(c))))
$(foreach i,$(FAM_TRAIN_IDS),$(eval $(call fam_train_rule,$(call fam_class,$(i)),$(call fam_inst,$(i)))))
$(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TRAIN),$(eval $(call fam_entry_rule,$(FAM_MB),$(c),$(n)))))
$(eval $(call baseline_models_rule,$(FAM_MB),$(filter %.pcd,$(FAM_MODELBASE))))
$(foreach i,$(FAM_BIG_IDS),$(eval $(call fam_entry_rule,$(FAM_BIG),$(call fam_class,$(i)),$(call fam_inst,$(i)))))
$(foreach p,$(FAM_BIG_WAITS),$(eval $(FAM_DIR)/train/$(firstword $(subst :, ,$(p)))/scan.pcd: | \
  $(FAM_DIR)/train/$(lastword $(subst :, ,$(p)))/noise-0/segments.json))
family-modelbase: $(FAM_BIG_MODELBASE)
ifneq ($(filter families,$(MAKECMDGOALS)),)
$(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TEST),$(foreach v,$(FAM_COVERS),\
  $(eval $(call fam_test_rule,$(c),$(n),$(v))))))
$(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TEST),$(foreach v,$(FAM_COVERS),$(foreach z,$(FAM_NOISES),\
  $(eval $(call fam_trial_rule,$(c),$(n),$(v),$(z)))))))

# The runs manifest: <verdict> <class> <instance> <cover> <noise>.
FAM_RUNS := $(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TEST),$(foreach v,$(FAM_COVERS),$(foreach z,$(FAM_NOISES),\
  $(FAM_DIR)/test/$(c)-$(n)/$(v)/noise-$(z)/verdict.json:$(c):$(n):$(v):$(z)))))
FAM_TRIAL_FILES := $(foreach r,$(FAM_RUNS),$(foreach d,$(dir $(firstword $(subst :, ,$(r)))),\
  $(d)verdict.json $(d)baseline-vfh.json $(d)baseline-fpfh.json))
$(FAM_DIR)/runs.txt: $(call text_prereq,$(FAM_DIR)/runs.txt,$(subst $(nl) ,$(nl),\
  $(foreach r,$(FAM_RUNS),$(subst :, ,$(r))$(nl))))
# The test renders are read by their trials' addnoise only (the 0 mm scan is a link to the
# render, deleted by fitvox): once the scores are written they are deleted unless KEEP=1.
FAM_TEST_SCANS := $(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TEST),$(foreach v,$(FAM_COVERS),\
  $(FAM_DIR)/test/$(c)-$(n)/$(v)/scan.pcd)))
.SECONDARY: $(FAM_TEST_SCANS)
$(FAM_RES)/confusion.csv: $(FAM_DIR)/runs.txt $(FAM_TRIAL_FILES) $(FAM_MODELBASE) $(call tool,famscore)
	@mkdir -p $(@D)
	@$(STAGE) $@ -- $(BIN)/famscore -i $(FAM_DIR)/runs.txt --modelbase $(FAM_MB) --confusion $@ \
	  --accuracy $(FAM_RES)/accuracy.csv --methods $(FAM_RES)/methods.csv \
	  --methods-confusion $(FAM_RES)/methods-confusion.csv$(if $(keep),, && rm -f $(FAM_TEST_SCANS))
$(filter-out %/confusion.csv,$(FAM_TABLES)): $(FAM_RES)/confusion.csv
families: $(FAM_TABLES)
endif
endif

# ---- the protocol inside `all`, and the report's "Vehicle families" section ---------------
# (report --families; docs/decisions/families.md §6, §9). With FAMILIES=1 (default) the report
# depends on famscore's tables, so `all` runs the protocol; it runs as a recursive
# `make families` (like the scene experiment), so its many rules are read only by that make.
# Under -q the sub-make is asked first (`make -q families`, which renders nothing), so
# `make -q all` exits 0 exactly when the protocol is up to date too; otherwise the step always
# runs (FORCE) and make compares the tables' times afterwards. The tools are built here first.
# FAMILIES=0 leaves the protocol out of `all` and of the report, unless this make runs the
# families target itself (`make families results/report.md`).
ifneq ($(filter families,$(MAKECMDGOALS))$(filter 1,$(FAMILIES)),)
$(RES)/report.md: $(FAM_RES)/confusion.csv $(FAM_RES)/accuracy.csv
REPORT_ARGS += --families $(FAM_RES)
endif
# Not in the scene experiment's own sub-make (`make scenes`, whose -q check would ask this one,
# and back); the sub-makes here never need the scene experiment (SCENE_EXPERIMENT=0).
ifeq ($(FAMILIES)$(filter families scenes,$(MAKECMDGOALS)),1)
ifneq ($(findstring q,$(make_letters)),q)
fam_force := FORCE
else
fam_force := $(if $(shell $(MAKE) -q --no-print-directory -f $(firstword $(MAKEFILE_LIST)) families \
  $(MAKEOVERRIDES) SCENE_EXPERIMENT=0 >/dev/null 2>&1 || echo stale),FORCE)
endif
$(FAM_RES)/confusion.csv: $(fam_force) $(foreach t,$(FAM_TOOLS),$(call tool,$(t)))
	+@$(MAKE) --no-print-directory -f $(firstword $(MAKEFILE_LIST)) families PROGRESS=0 SCENE_EXPERIMENT=0
$(filter-out %/confusion.csv,$(FAM_TABLES)): $(FAM_RES)/confusion.csv
endif
