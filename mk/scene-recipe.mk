# The scene experiment's tile recipe (issue 16; docs/decisions/scene-experiment.md): the recipe's
# variables and scene_recipe(cover, seed), the text `make scenes` writes as
# out/scenes/<cover>/tile-<seed>/recipe.scene. mk/scenes.mk includes this file: its one copy.
# Read on its own it writes the recipes make renders, without reading the experiment graph (no
# manifest, no options file, nothing under OUT):
#   make -f mk/scene-recipe.mk SCENE_RECIPES=DIR SCENE_SEEDS="101 102" SCENE_COVERS="light dense" \
#     [SCENE_SENSOR=als_qL1 SCENE_SENSOR_KEYS="pulse_rate=... speed=..."] [other SCENE_* of the recipe]
# -> DIR/<cover>-<seed>.scene, byte for byte the recipe.scene of `make scenes` with the same
# variables (bench/detect/recipes.sh; checked by tests/pipeline/make_graph.sh). Run it from the
# source tree's root (scripts/cksum.sh); a dry run (-n) writes them too.
# (Read on its own: what Makefile.experiments gives every included file, before anything here.)
ifneq ($(filter %scene-recipe.mk,$(firstword $(MAKEFILE_LIST))),)
SHELL := /bin/bash
define nl


endef
space := $(subst ,, )
endif
SCENE_EXTENT ?= 30m
SCENE_MODELS ?= earthmover,obj1,sedan,semi,tank
# Cover knobs per level: random trees per hectare and trees planted beside each vehicle.
SCENE_TREES_light ?= 100
SCENE_HIDE_light ?= 0
SCENE_TREES_medium ?= 350
SCENE_HIDE_medium ?= 1
SCENE_TREES_dense ?= 700
SCENE_HIDE_dense ?= 2
# Pixel spacing (docs/decisions/scene-experiment.md, "Operating point"): 40 mm with the tile
# fitvox setting (share/params/fitvox-tile.ini).
SCENE_SPACING ?= 40mm
# Sensor mode (docs/decisions/sensor.md; docs/decisions/density-ladder.md, "The ladder on the
# realistic sensor"): SCENE_SENSOR=<preset of share/sensors/> renders every tile with that
# sensor (pulses with a footprint, multiple returns, the preset's flight lines along the
# recipe's headings) instead of the four image looks at SCENE_SPACING; SCENE_SENSOR_KEYS=
# "KEY=VALUE ..." become the recipe's `sensor.KEY = VALUE` lines. rangetrace then writes the
# trajectory <tile>/scan.traj beside the scan, and detect derives each point's direction toward
# the sensor from it (--trajectory), so the candidates carry sensor_x/y/z as an image-mode scan's
# do (classify's sight lines, fitvox's normals, verify). Empty (the default): the recipes and
# rules of image mode, byte for byte.
SCENE_SENSOR ?=
SCENE_SENSOR_KEYS ?=
ifneq ($(SCENE_SENSOR),)
$(if $(filter 1,$(words $(SCENE_SENSOR))),,$(error SCENE_SENSOR=$(SCENE_SENSOR) must name one preset of share/sensors/))
$(if $(wildcard share/sensors/$(SCENE_SENSOR).ini),,$(error SCENE_SENSOR=$(SCENE_SENSOR): no share/sensors/$(SCENE_SENSOR).ini))
$(foreach k,$(SCENE_SENSOR_KEYS),$(if $(shell printf '%s' '$(k)' | grep -xE '[a-z_]+=[^=]+'),,$(error \
  SCENE_SENSOR_KEYS: $(k) is not KEY=VALUE)))
else
$(if $(strip $(SCENE_SENSOR_KEYS)),$(error SCENE_SENSOR_KEYS=$(SCENE_SENSOR_KEYS) needs SCENE_SENSOR))
endif
# Clutter per tile (issue 29, "unseen clutter"; docs/decisions/scene-experiment.md): the kinds
# verify's and classify's thresholds were fitted on, then two of the six unseen kinds, by tile
# (cksum of clutter/<cover>/<seed> mod 3: trailer + rock, caravan + tent, pipes + barriers; all
# six in one 30 m tile of 3 - 8 vehicles leave no room). SCENE_CLUTTER="boulder 2 container 1
# logs 1" is the ablation value: the seen kinds alone, the recipe before issue 29.
SCENE_CLUTTER ?= boulder 2 container 1 logs 1 $(call scene_unseen,$(1)/$(2))
scene_unseen = $(subst _, ,$(word $(shell . scripts/cksum.sh --mod 3 --add 1 'clutter/$(1)'),\
  trailer_1_rock_1 caravan_1_tent_1 pipes_1_barriers_1))
# Vehicles per tile: SCENE_VEHICLES, else 3 - 8 from the seed.
SCENE_VEHICLES ?=
scene_vehicles = $(or $(SCENE_VEHICLES),$(shell . scripts/cksum.sh --mod 6 --add 3 'vehicles/$(1)'))

# The recipe of one tile (cover, seed).
define scene_recipe
# scene experiment tile (mk/scenes.mk): cover $(1), seed $(2)
extent = $(SCENE_EXTENT)
terrain = rolling 1m 25m
trees = $(SCENE_TREES_$(1))
hide = $(SCENE_HIDE_$(1))
bushes = 300
vehicles = random $(call scene_vehicles,$(1)/$(2)) from $(SCENE_MODELS)
clutter = $(SCENE_CLUTTER)
$(if $(SCENE_SENSOR),$(scene_sensor_lines),$(scene_image_lines))
endef
# The render's lines: the four image looks at SCENE_SPACING, or the sensor (SCENE_SENSOR).
define scene_image_lines
flight_lines = 2
headings = 0deg 90deg
looks = 75deg/0deg 75deg/180deg
spacing = $(SCENE_SPACING)
endef
define scene_sensor_lines
headings = 0deg 90deg
sensor = $(SCENE_SENSOR)$(subst $(space)$(nl),$(nl),$(foreach k,$(SCENE_SENSOR_KEYS),$(nl)sensor.$(subst =, = ,$(k))))
endef

# ---- read on its own: the recipes into SCENE_RECIPES ----------------------------------------
ifneq ($(filter %scene-recipe.mk,$(firstword $(MAKEFILE_LIST))),)
$(foreach v,SCENE_RECIPES SCENE_SEEDS SCENE_COVERS,$(if $(strip $($(v))),,$(error scene-recipe.mk: $(v) is not set)))
# (make expands a recipe before it runs it: the directory is made by the expansion, first.)
scene_recipes_write = $(shell mkdir -p $(SCENE_RECIPES))$(foreach c,$(SCENE_COVERS),$(foreach s,$(SCENE_SEEDS),\
  $(file >$(SCENE_RECIPES)/$(c)-$(s).scene,$(call scene_recipe,$(c),$(s)))))
.PHONY: scene-recipes
scene-recipes:
	@:$(scene_recipes_write)
endif
