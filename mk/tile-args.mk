# The arguments of `make tile` and `make tiles` (mk/scenes.mk), checked when the makefile is
# read, before anything is written: Makefile.experiments includes this file ahead of the progress
# count, whose planning creates OUT and OUT/.progress* (stop 70: a refused `make tile` had left
# OUT and its .progress files behind, and without OUT=... its files went into the experiment's
# out/). docs/decisions/hardening.md "The tile workflow's arguments".

# one_word(WHAT, VALUE): an error unless VALUE is one word. make splits its words at blanks, so a
# file name with a space cannot be a target or a prerequisite (before: "TILE=... does not exist"
# for a file that exists, and with an OUT holding a space thousands of make warnings and a
# directory named after its second word).
one_word = $(if $(filter-out 0 1,$(words $(2))),$(error $(1)=$(2) holds a blank: make cannot handle \
  file names with spaces; use a name without one (for an input file, a link or a copy)))
# own_out(GOAL): an error unless OUT was given (not the experiment's default out/) and names a
# directory of its own: not ".", "..", "/", nor the directory make runs in.
own_out = $(if $(filter command line environment environment override override,$(origin OUT)),,$(error \
  $(1): give OUT=<the output directory> (the default, $(OUT)/, is the experiment's own))) $(call \
  one_word,$(1): OUT,$(OUT))$(if $(filter . .. /,$(patsubst %/,%,$(OUT)))$(filter $(CURDIR) /,$(realpath \
  $(OUT))),$(error $(1): OUT=$(OUT) must name the tile's own output directory))

ifneq ($(filter tile,$(MAKECMDGOALS)),)
$(if $(TILE),,$(error tile: give TILE=<the tile: .las, .laz, .pcd or .ply with x y z>))
$(call one_word,tile: TILE,$(TILE))
$(if $(wildcard $(TILE)),,$(error tile: TILE=$(TILE) does not exist))
$(call own_out,tile)
$(if $(filter 1,$(words $(MODELBASE))),,$(error tile: give MODELBASE=<directory of <model>.json graphs and <model>.pcd \
  surfaces>$(if $(MODELBASE), (one word; make cannot handle file names with spaces))))
$(if $(wildcard $(patsubst %/,%,$(MODELBASE))/*.json),,$(error tile: MODELBASE=$(patsubst %/,%,$(MODELBASE)) holds no \
  <model>.json graph (make -f Makefile.experiments verify-modelbase builds out/modelbase)))
$(if $(CRS),$(if $(shell printf '%s' '$(CRS)' | grep -xE 'EPSG:[1-9][0-9]{0,5}'),,$(error tile: CRS=$(CRS) must be EPSG:<code>)))
# TRAJECTORY=<file>: the sensor's path (formats/README.md "Trajectory"; rangetrace writes
# <scan>.traj beside a sensor tile) for verify's sensor directions (docs/decisions/verify.md §13).
$(if $(TRAJECTORY),$(if $(filter 1,$(words $(TRAJECTORY))),,$(error tile: TRAJECTORY=$(TRAJECTORY) must name one file)))
$(if $(TRAJECTORY),$(if $(wildcard $(TRAJECTORY)),,$(error tile: TRAJECTORY=$(TRAJECTORY) does not exist)))
endif

# The stages' parameters `make tile` and `make tiles` take (stop 71, review F12): TILE_DETECT,
# TILE_FITVOX, TILE_CLASSIFY and MODEL_CLASSES name files that must exist, TILE_MODEL_DENSITY is
# a number of points/m². mk/scenes.mk, read after the progress count, gives their defaults and
# checks them for every goal (the scene experiment reads them too); for these two goals they are
# checked here as well, when given, so a refused run leaves nothing in OUT (the planning had
# created OUT/.progress*), and TILE_FITVOX is checked at all (before, a missing one ran detect
# and the plan, then stopped on make's "No rule to make target '<file>', needed by
# '<OUT>/cands/c0001/samples.pcd'"). TILE_DETECT may be empty (detect's own defaults); the others
# may not.
# tile_param_file(VARIABLE, WHOSE, EMPTY_OK): the check of one parameter file, when the variable
# is set (its default, from mk/scenes.mk, is the repository's own file).
tile_param_file = $(if $(filter undefined,$(origin $(1))),,$(call one_word,$(tile_goal): $(1),$($(1)))$(if \
  $(strip $($(1))),$(if $(wildcard $($(1))),,$(error $(tile_goal): $(1)=$($(1)) does not exist ($(2)))),$(if \
  $(3),,$(error $(tile_goal): $(1) is empty: give $(2) or leave it out for the default))))
tile_goal := $(firstword $(filter tile tiles,$(MAKECMDGOALS)))
ifneq ($(tile_goal),)
$(call tile_param_file,TILE_DETECT,detect's parameters,empty ok)
$(call tile_param_file,TILE_FITVOX,fitvox's parameters on the candidates)
$(call tile_param_file,TILE_CLASSIFY,classify's parameters)
$(call tile_param_file,MODEL_CLASSES,the thesis models' classes)
$(if $(filter undefined,$(origin TILE_MODEL_DENSITY)),,$(if $(shell printf '%s' '$(TILE_MODEL_DENSITY)' | grep -xE \
  '[0-9]+(\.[0-9]+)?'),,$(error $(tile_goal): TILE_MODEL_DENSITY=$(TILE_MODEL_DENSITY) must be a number of points/m²)))
endif

# `make tiles`: the tiles are the directory's .las, .laz and .pcd files, the extension in either
# case (PLOT1.LAZ as plot1.laz; before stop 70 only lower case).
ifneq ($(filter tiles,$(MAKECMDGOALS)),)
$(if $(TILES),,$(error tiles: give TILES=<directory of .las/.laz/.pcd tiles>))
$(call one_word,tiles: TILES,$(TILES))
$(call own_out,tiles)
TILES_FILES := $(sort $(foreach x,las laz pcd LAS LAZ PCD Las Laz Pcd,$(wildcard $(patsubst %/,%,$(TILES))/*.$(x))))
$(if $(TILES_FILES),,$(error tiles: TILES=$(TILES) holds no .las, .laz or .pcd file))
$(if $(filter-out $(words $(TILES_FILES)),$(words $(sort $(basename $(notdir $(TILES_FILES)))))),\
  $(error tiles: two tiles in $(TILES) have the same name without extension))
endif
