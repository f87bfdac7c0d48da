# The open-set experiment (issue 29, "Unseen vehicles"; docs/decisions/open-set.md), included by
# Makefile.experiments after mk/scenes.mk and mk/usermb.mk. Part of `all` with the scene
# experiment (OPENSET follows SCENE_EXPERIMENT unless given):
#
#   make -f Makefile.experiments openset -j2 [OPENSET_SEEDS="31 32"] [OPENSET_COVERS=light]
#
# The vehicle library of third-party meshes (share/vehicles: catalogue.csv, split.csv) split
# into modelbase instances and test instances that never overlap:
#   share/vehicles/modelbase/<class>__<name>.ply   the modelbase instances (committed links)
#   out/openset/modelbase/<class>__<name>.{json,pcd,class}   `make user-modelbase` on them
#   out/openset/classes.csv                    model,class of every instance (score --model-classes)
#   out/openset/tiles/<cover>/tile-<seed>/...  the scene experiment's tiles (mk/scenes.mk: its
#                                              recipe and cover levels, noise 0) whose vehicles
#                                              are drawn from the TEST instances only
#   results/openset/score.json (+ CSV tables)  scored against their truth: the class of each
#                                              answer (model answers: their entry's class)
# The report's section "Open set: unseen vehicles" reads the score (report --openset).
comma := ,
OPENSET ?= $(SCENE_EXPERIMENT)
$(if $(filter-out 0 1,$(OPENSET)),$(error OPENSET=$(OPENSET): must be 0 or 1))
OPENSET_SEEDS ?= 31 32 33 34
OPENSET_COVERS ?= light medium
OPENSET_LIBRARY ?= share/vehicles
OPENSET_DIR := $(OUT)/openset
OPENSET_RES := $(RES)/openset
OPENSET_MB := $(OPENSET_DIR)/modelbase
# The modelbase instances as user-modelbase takes them: links <class>__<name>.ply to the
# library's meshes (committed; test_vehicles checks them against split.csv).
OPENSET_MESHES := $(OPENSET_LIBRARY)/modelbase
OPENSET_SCORE := $(OPENSET_RES)/score.json
# NAME:CLASS:FILE:SPLIT of every library mesh (catalogue.csv joined with split.csv; one shell,
# only where the open set is read: every parse pays for its shells, docs/decisions/cost.md).
ifneq ($(filter 1,$(OPENSET))$(filter openset,$(MAKECMDGOALS)),)
openset_rows := $(shell awk -F, 'FNR == 1 { next } FILENAME ~ /split/ { s[$$1] = $$3; next } \
  { print $$1 ":" $$2 ":" $$3 ":" s[$$1] }' $(OPENSET_LIBRARY)/split.csv $(OPENSET_LIBRARY)/catalogue.csv)
endif
openset_split = $(foreach r,$(openset_rows),$(if $(filter $(1),$(word 4,$(subst :, ,$(r)))),$(r)))
openset_name = $(word 1,$(subst :, ,$(1)))
openset_class = $(word 2,$(subst :, ,$(1)))
openset_file = $(OPENSET_LIBRARY)/$(word 3,$(subst :, ,$(1)))
OPENSET_TRAIN := $(call openset_split,modelbase)
OPENSET_TEST := $(call openset_split,test)
$(if $(filter 1,$(OPENSET))$(filter openset,$(MAKECMDGOALS)),$(if $(and $(OPENSET_TRAIN),$(OPENSET_TEST)),,$(error OPENSET: $(OPENSET_LIBRARY) has no \
  modelbase or no test instance in split.csv)))
# The test meshes as the recipe's random list (absolute paths: the recipe lives under OUT).
openset_models = $(subst $(space),$(comma),$(strip $(foreach r,$(OPENSET_TEST),$(abspath $(call openset_file,$(r))))))
# model,class of every instance: the test meshes by their names (the truth's model), the
# modelbase entries by theirs (a model answer's model).
define openset_classes
model,class
$(foreach r,$(OPENSET_TEST),$(call openset_name,$(r)),$(call openset_class,$(r))
)$(foreach r,$(OPENSET_TRAIN),$(call openset_class,$(r))__$(call openset_name,$(r)),$(call openset_class,$(r))
)
endef

ifeq ($(filter scenes user-modelbase,$(MAKECMDGOALS)),)
ifeq ($(OPENSET),1)
$(if $(dry_run),,$(shell mkdir -p $(OPENSET_DIR) $(OPENSET_RES)))
$(OPENSET_DIR)/classes.csv: $(call text_prereq,$(OPENSET_DIR)/classes.csv,$(subst $(nl)$(space),$(nl),$(openset_classes)))
endif
# The sub-makes: the modelbase, then the tiles (both redo only what is out of date). Under -q
# they are asked (only with OPENSET=1); otherwise they always run and make compares times.
openset_mb_args = --no-print-directory -f $(firstword $(MAKEFILE_LIST)) user-modelbase PROGRESS=0 \
  MESHES=$(OPENSET_MESHES) MODELBASE=$(OPENSET_MB)
openset_args = --no-print-directory -f $(firstword $(MAKEFILE_LIST)) scenes PROGRESS=0 \
  SCENE_DIR=$(OPENSET_DIR)/tiles SCENE_RES=$(OPENSET_RES) SCENE_MB=$(OPENSET_MB) \
  SCENE_MODELS=$(openset_models) SCENE_MODEL_CLASSES=$(OPENSET_DIR)/classes.csv \
  SCENE_SEEDS="$(OPENSET_SEEDS)" SCENE_COVERS="$(OPENSET_COVERS)" SCENE_NOISES=0 SCENE_BASELINE= \
  SCENE_SIZE_ONLY=0 SCENE_PICTURES=0
ifneq ($(findstring q,$(make_letters))$(OPENSET),q1)
openset_force := FORCE
else
openset_force := $(if $(shell { $(MAKE) -q $(MAKEOVERRIDES) $(openset_mb_args) && \
  $(MAKE) -q $(MAKEOVERRIDES) $(openset_args); } >/dev/null 2>&1 || echo stale),FORCE)
endif
$(if $(filter meshsize,$(TOOLS)),,$(eval $(call tool_rule,meshsize)))
OPENSET_TOOLS := meshsize rangetrace detect classify fitvox cocone ncut gmatch verify collect score
$(OPENSET_MB)/.built: $(openset_force) $(wildcard $(OPENSET_MESHES)/*) $(foreach t,$(OPENSET_TOOLS),$(call tool,$(t)))
	+@$(MAKE) $(openset_mb_args)$(if $(dry_run),, && touch $@)
$(OPENSET_SCORE): $(openset_force) $(OPENSET_MB)/.built $(OPENSET_DIR)/classes.csv $(MODELBASE) $(VERIFY_SURFACES)
	+@$(MAKE) $(openset_args)
.PHONY: openset
openset: $(OPENSET_SCORE)
ifeq ($(OPENSET),1)
$(RES)/report.md: $(OPENSET_SCORE)
REPORT_ARGS += --openset $(OPENSET_SCORE)
endif
endif
