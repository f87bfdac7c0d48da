# verify (issue 15; docs/decisions/verify.md), included by Makefile.experiments.
#   make -f Makefile.experiments verify-modelbase    model graphs + surfaces (<model>.pcd)
#   make -f Makefile.experiments verdicts            verdict.json beside every match.json
#   make -f Makefile.experiments band-modelbase      graphs + surfaces from the band scene
# A modelbase entry is the graph <model>.json plus its surface samples with normals,
# <model>.pcd = the unoccluded noise-0 samples (verify keeps the label-1 rows).
# verify is in TOOLS (Makefile.experiments), which gives it its build rule and stamp.

VERIFY_SURFACES := $(foreach o,$(OBJECTS),$(OUT)/modelbase/$(o).pcd)
$(OUT)/modelbase/%.pcd: $(OUT)/%/unoccluded/noise-0/samples.pcd
	@mkdir -p $(@D) && cp $< $(@D)/.$*.tmp$$$$.pcd && mv $(@D)/.$*.tmp$$$$.pcd $@ && echo "done  $@"
.PHONY: verify-modelbase verdicts band-modelbase
verify-modelbase: $(MODELBASE) $(VERIFY_SURFACES)

# thesis_verify_rule(OBJECT, SCENE, NOISE): verify on one thesis trial's match.
define thesis_verify_rule
$(OUT)/$(1)/$(2)/noise-$(3)/verdict.json: $(OUT)/$(1)/$(2)/noise-$(3)/match.json \
    $(OUT)/$(1)/$(2)/noise-$(3)/samples.pcd $(MODELBASE) $(VERIFY_SURFACES) $(call tool,verify) $(P)/verify.ini $(opts.params)
	@$(STAGE) $$@ -- $(BIN)/verify --config $(P)/verify.ini -i $$< \
	  --points $(OUT)/$(1)/$(2)/noise-$(3)/samples.pcd --segments $(OUT)/$(1)/$(2)/noise-$(3)/segments.json \
	  --modelbase $(OUT)/modelbase -o $$@
endef
$(foreach o,$(OBJECTS),$(foreach s,$(SCENES),$(foreach n,$(NOISES),$(eval $(call thesis_verify_rule,$(o),$(s),$(n))))))
VERDICTS := $(addsuffix /verdict.json,$(CASES))
verdicts: $(VERDICTS)

# The band modelbase (share/scenes/band.scene: the trials' 75-degree elevation all around).
# rangetrace knows circle/flyby/unoccluded by name; the band recipe is given as a file.
define band_scene_rule
$(OUT)/$(1)/band/scan.pcd: $(call tool,rangetrace) $(P)/rangetrace.ini share/models/$(1).inc share/scenes/band.scene \
    $(opts.params)
	@$(STAGE) $$@ -- $(BIN)/rangetrace --config $(P)/rangetrace.ini --model $(1) --scene share/scenes/band.scene \
	  --seed $$(call seed,$(1)/band) --threads 2 -o $$@
endef
$(foreach o,$(OBJECTS),$(eval $(call band_scene_rule,$(o))))
$(foreach o,$(OBJECTS),$(eval $(call case_rule,$(o),band,0)))
$(OUT)/modelbase-band/%.json: $(OUT)/%/band/noise-0/segments.json
	@mkdir -p $(@D) && cp $< $(@D)/.$*.tmp$$$$.json && mv $(@D)/.$*.tmp$$$$.json $@ && echo "done  $@"
$(OUT)/modelbase-band/%.pcd: $(OUT)/%/band/noise-0/samples.pcd
	@mkdir -p $(@D) && cp $< $(@D)/.$*.tmp$$$$.pcd && mv $(@D)/.$*.tmp$$$$.pcd $@ && echo "done  $@"
band-modelbase: $(foreach o,$(OBJECTS),$(OUT)/modelbase-band/$(o).json $(OUT)/modelbase-band/$(o).pcd)
