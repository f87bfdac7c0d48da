# Vehicle families, class-level mini protocol (issue 17; docs/decisions/families.md), included
# by Makefile.experiments. NOT part of `all`.
#
#   make -f Makefile.experiments families -j2 [FAM_CLASSES="pickup van" FAM_TRAIN="0 1"
#        FAM_TEST="1000" FAM_COVERS=light FAM_NOISES=0]
#   make -f Makefile.experiments families results/report.md -j2   ... and the report with its
#        "Vehicle families" section (a later report, e.g. from `all`, keeps it while the tables exist)
#
# Modelbase: instances FAM_TRAIN of every class in FAM_CLASSES (procedural, rangetrace --model
# family:<class>:<n>), rendered with the modelbase's `unoccluded` views and taken through the
# same stages as verify-modelbase (addnoise 0 mm, fitvox, cocone, ncut):
#   out/families/train/<class>-<n>/{scan.pcd, noise-0/{scan,samples}.pcd, mesh.ply, segments.json}
#   out/families/modelbase/<class>-<n>.{json,pcd,class}
# Tests: OTHER instances (FAM_TEST, disjoint from FAM_TRAIN) at a random heading from the seed,
# under foliage of each cover level, with each noise level, through
# addnoise | fitvox | cocone | ncut | gmatch | verify -k FAM_TOPK:
#   out/families/test/<class>-<n>/<cover>/scan.pcd                rendered once per cover
#   out/families/test/<class>-<n>/<cover>/noise-<mm>/{scan.pcd, samples.pcd, mesh.ply,
#                                                    segments.json, match.json, verdict.json}
#   results/families/{confusion.csv, accuracy.csv}                 famscore over every verdict
# A stage failing on its input (e.g. cocone on a candidate that foliage left in pieces) is
# recorded (stage.sh --record-failure): the trial's verdict is empty and counts as class none.
FAM_CLASSES ?= sedan hatchback suv pickup van box-truck semi-tractor bus wheeled-apc tracked-apc \
  tank wheel-loader
FAM_TRAIN ?= 0 1 2
FAM_TEST ?= 1000 1001
# Cover levels (the scene experiment's names): foliage discs over the vehicle's square.
FAM_COVERS ?= light medium dense
FAM_FOLIAGE_light ?= 250
FAM_FOLIAGE_medium ?= 500
FAM_FOLIAGE_dense ?= 800
FAM_NOISES ?= 0 8 32
FAM_VIEWS ?= circle 12 75deg
FAM_TOPK ?= 5
# Image and crop box large enough for a 13.5 m bus and a 4 m semi-tractor (the thesis's 10 x 4
# x 4 m box would cut them); the thesis's 30 mm pixel spacing, which fitvox is tuned to.
FAM_RENDER ?= --size 640 --spacing 30mm --crop-length 15m --crop-width 5m --crop-height 4.6m
FAM_DIR := $(OUT)/families
FAM_MB := $(FAM_DIR)/modelbase
FAM_RES := $(RES)/families

.PHONY: families FORCE
FORCE:
ifneq ($(filter families,$(MAKECMDGOALS)),)
$(if $(filter $(FAM_TRAIN),$(FAM_TEST)),$(error families: FAM_TEST and FAM_TRAIN share instances \
  ($(filter $(FAM_TRAIN),$(FAM_TEST))); the tests must be other instances))
$(foreach c,$(FAM_COVERS),$(if $(FAM_FOLIAGE_$(c)),,$(error families: no FAM_FOLIAGE_$(c) for cover $(c))))
$(if $(filter famscore,$(TOOLS)),,$(eval $(call tool_rule,famscore)))
# famscore links the family generator (class ranges, instance sizes) from tools/rangetrace.
$(BIN)/famscore: $(call code_in,tools/rangetrace)
fam_heading = $(shell echo $$(( $(call seed,families/heading/$(1)) % 360 )))deg

# The test scenes: one recipe per cover level (rewritten only when its text changes).
define fam_scene_rule
$(FAM_DIR)/scenes/$(1).scene: FORCE
	@mkdir -p $$(@D) && printf '%s\n' '# families protocol (mk/families.mk): cover $(1)' \
	  'foliage_count = $(FAM_FOLIAGE_$(1))' 'foliage_radius = 100mm' 'foliage_band = 2m' \
	  'foliage_square = 16m' 'views = $(FAM_VIEWS)' >$$@.tmp && { cmp -s $$@.tmp $$@ && rm $$@.tmp || mv $$@.tmp $$@; }
endef

# fam_chain(DIR, NOISE, SEEDKEY, FAIL): addnoise -> fitvox -> cocone -> ncut on DIR/scan.pcd.
define fam_chain
$(1)/noise-$(2)/scan.pcd: $(1)/scan.pcd $(call tool,addnoise) $(P)/addnoise.ini
	@$(STAGE) $(4) $$@ -- $(BIN)/addnoise --config $(P)/addnoise.ini --sigma $(2)mm \
	  --seed $(call seed,$(3)/$(2)) -i $$< -o $$@
$(1)/noise-$(2)/samples.pcd: $(1)/noise-$(2)/scan.pcd $(call tool,fitvox) $(P)/fitvox.ini
	@$(STAGE) $(4) $$@ -- $(BIN)/fitvox --config $(P)/fitvox.ini -i $$< -o $$@
$(1)/noise-$(2)/mesh.ply: $(1)/noise-$(2)/samples.pcd $(call tool,cocone) $(P)/cocone.ini
	@$(STAGE) $(4) $$@ -- $(BIN)/cocone --config $(P)/cocone.ini -i $$< -o $$@
$(1)/noise-$(2)/segments.json: $(1)/noise-$(2)/mesh.ply $(call tool,ncut) $(P)/ncut.ini
	@$(STAGE) $(4) $$@ -- $(BIN)/ncut --config $(P)/ncut.ini --seed $(call seed,$(3)/$(2)) -i $$< \
	  -o $$@ --colored $(1)/noise-$(2)/segments.ply
endef

# fam_train_rule(class, n): one modelbase entry.
define fam_train_rule
$(FAM_DIR)/train/$(1)-$(2)/scan.pcd: $(call tool,rangetrace) $(P)/rangetrace.ini share/scenes/unoccluded.scene
	@$(STAGE) $$@ -- $(BIN)/rangetrace --config $(P)/rangetrace.ini $(FAM_RENDER) --model family:$(1):$(2) \
	  --scene unoccluded --seed $(call seed,families/train/$(1)-$(2)) --threads 2 -o $$@
$(call fam_chain,$(FAM_DIR)/train/$(1)-$(2),0,families/train/$(1)-$(2),)
$(FAM_MB)/$(1)-$(2).json: $(FAM_DIR)/train/$(1)-$(2)/noise-0/segments.json
	@mkdir -p $$(@D) && cp $$< $$(@D)/.$(1)-$(2).tmp$$$$$$$$.json && mv $$(@D)/.$(1)-$(2).tmp$$$$$$$$.json $$@ && echo "done  $$@"
$(FAM_MB)/$(1)-$(2).pcd: $(FAM_DIR)/train/$(1)-$(2)/noise-0/samples.pcd
	@mkdir -p $$(@D) && cp $$< $$(@D)/.$(1)-$(2).tmp$$$$$$$$.pcd && mv $$(@D)/.$(1)-$(2).tmp$$$$$$$$.pcd $$@ && echo "done  $$@"
$(FAM_MB)/$(1)-$(2).class:
	@mkdir -p $$(@D) && echo $(1) >$$(@D)/.$(1)-$(2).tmp$$$$$$$$ && mv $$(@D)/.$(1)-$(2).tmp$$$$$$$$ $$@ && echo "done  $$@"
endef

FAM_ENTRIES := $(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TRAIN),$(FAM_MB)/$(c)-$(n)))
FAM_MODELBASE := $(foreach e,$(FAM_ENTRIES),$(e).json $(e).pcd $(e).class)

# fam_test_rule(class, n, cover): the render; fam_trial_rule(class, n, cover, noise): the trial.
define fam_test_rule
$(FAM_DIR)/test/$(1)-$(2)/$(3)/scan.pcd: $(FAM_DIR)/scenes/$(3).scene $(call tool,rangetrace) $(P)/rangetrace.ini
	@$(STAGE) $$@ -- $(BIN)/rangetrace --config $(P)/rangetrace.ini $(FAM_RENDER) --model family:$(1):$(2) \
	  --scene $$< --heading $(call fam_heading,$(1)-$(2)/$(3)) --seed $(call seed,families/test/$(1)-$(2)/$(3)) \
	  --threads 2 -o $$@
endef
define fam_trial_rule
$(call fam_chain,$(FAM_DIR)/test/$(1)-$(2)/$(3),$(4),families/test/$(1)-$(2)/$(3),--record-failure)
$(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/match.json: $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/segments.json \
    $(FAM_MODELBASE) $(call tool,gmatch) $(P)/gmatch.ini
	@$(STAGE) --record-failure $$@ -- $(BIN)/gmatch --config $(P)/gmatch.ini -i $$< --modelbase $(FAM_MB) -o $$@
$(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/verdict.json: $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/match.json \
    $(FAM_MODELBASE) $(call tool,verify) $(P)/verify.ini
	@$(STAGE) --record-failure $$@ -- $(BIN)/verify --config $(P)/verify.ini -k $(FAM_TOPK) -i $$< \
	  --points $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/samples.pcd \
	  --segments $(FAM_DIR)/test/$(1)-$(2)/$(3)/noise-$(4)/segments.json --modelbase $(FAM_MB) -o $$@
endef

$(foreach c,$(FAM_COVERS),$(eval $(call fam_scene_rule,$(c))))
$(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TRAIN),$(eval $(call fam_train_rule,$(c),$(n)))))
$(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TEST),$(foreach v,$(FAM_COVERS),\
  $(eval $(call fam_test_rule,$(c),$(n),$(v))))))
$(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TEST),$(foreach v,$(FAM_COVERS),$(foreach z,$(FAM_NOISES),\
  $(eval $(call fam_trial_rule,$(c),$(n),$(v),$(z)))))))

# The runs manifest: <verdict> <class> <instance> <cover> <noise> (rewritten only when its text changes).
FAM_RUNS := $(foreach c,$(FAM_CLASSES),$(foreach n,$(FAM_TEST),$(foreach v,$(FAM_COVERS),$(foreach z,$(FAM_NOISES),\
  $(FAM_DIR)/test/$(c)-$(n)/$(v)/noise-$(z)/verdict.json:$(c):$(n):$(v):$(z)))))
$(FAM_DIR)/runs.txt: FORCE
	@mkdir -p $(@D) && printf '%s\n' $(foreach r,$(FAM_RUNS),'$(subst :, ,$(r))') >$@.tmp && \
	  { cmp -s $@.tmp $@ && rm $@.tmp || mv $@.tmp $@; }
$(FAM_RES)/confusion.csv: $(FAM_DIR)/runs.txt $(foreach r,$(FAM_RUNS),$(firstword $(subst :, ,$(r)))) \
    $(FAM_MODELBASE) $(call tool,famscore)
	@mkdir -p $(@D)
	@$(STAGE) $@ -- $(BIN)/famscore -i $(FAM_DIR)/runs.txt --modelbase $(FAM_MB) --confusion $@ \
	  --accuracy $(FAM_RES)/accuracy.csv
$(FAM_RES)/accuracy.csv: $(FAM_RES)/confusion.csv
families: $(FAM_RES)/confusion.csv $(FAM_RES)/accuracy.csv
endif

# The report's "Vehicle families" section (report --families; docs/decisions/families.md §6):
# when this make runs the families target, or an earlier one left both tables. `all` does not
# run the protocol, and without the tables the report is unchanged.
ifneq ($(filter families,$(MAKECMDGOALS))$(and $(wildcard $(FAM_RES)/confusion.csv),$(wildcard $(FAM_RES)/accuracy.csv)),)
$(RES)/report.md: $(FAM_RES)/confusion.csv $(FAM_RES)/accuracy.csv
REPORT_ARGS += --families $(FAM_RES)
endif
