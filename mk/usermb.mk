# A modelbase from the user's own vehicle meshes in one command (issue 27;
# docs/decisions/user-modelbase.md), included by Makefile.experiments. Read only when the goal is
# user-modelbase, so other makes pay nothing.
#
#   make -f Makefile.experiments user-modelbase MESHES=DIR MODELBASE=DIR -j2
#        [MESH_UNITS=mm|cm|m] [MESH_UP=y|z] [MESH_CROP_LENGTH=14m] [MESH_UP_CHECK=refuse|warn|off]
#
# Every mesh DIR/<name>.obj|.ply|.stl (names: words of [A-Za-z0-9_.-]) becomes the entry
#   MODELBASE/<name>.json    the segment graph gmatch matches
#   MODELBASE/<name>.pcd     the surface samples verify poses
#   MODELBASE/<name>.class   its class, one word, when it has one
# the layout family-modelbase and verify-modelbase write, so gmatch/verify --modelbase and
# `make tile MODELBASE=...` read it as it is. The class: "<class>__<rest>" in the file name gives
# <class> (car__ford_focus.obj: car); a row "<name>,<class>" of DIR/classes.csv (header
# "name,class") overrides it; a mesh with neither gets no .class (a warning says so; verify then
# answers no class when it picks that entry).
# The chain is the modelbase's (verify-modelbase, family-modelbase): rangetrace with the
# `unoccluded` views and share/params/rangetrace.ini, MESH_UNITS/MESH_UP (default m, z up);
# the crop box and image are rangetrace.ini's unless the mesh (measured by meshsize) overflows
# them (scripts/usermb-crop.sh; MESH_CROP_LENGTH fixes the length for every mesh); then the
# 0 mm link, fitvox, cocone, ncut, as fam_chain (mk/families.mk) runs them. meshsize also checks
# that the mesh stands upright as read (`--up-check`; user-modelbase.md, stop 67): a mesh that
# looks on its side (a y-up mesh read as z up, or the reverse) or on its end stops its entry
# before the render, with the MESH_UP to give (MESH_UP_CHECK=refuse, the default); =warn renders
# it anyway and prints meshsize's warning, =off skips the check. The check changes no size.txt.
# Work directory:
#   MODELBASE/.work/<name>/{import.txt, size.txt, noise-0/{samples.pcd, mesh.ply,
#                           segments.json, segments.ply}} and every stage's .log and .time
# The two scans (scan.pcd, noise-0/scan.pcd, 15-80 MB each) are deleted once read (.SECONDARY,
# as in families). The entries' .json and .pcd are hard links to the work files (copies where
# the filesystem has none); the .pcd is placed only once the chain has made the .json's graph
# (stop 71, review F17: a chain that failed in cocone left MODELBASE/<name>.pcd without its
# .json, half an entry; an order-only prerequisite, since the .pcd, a link to samples.pcd, is
# older than the graph). import.txt holds the mesh's file, units, up axis and crop length
# (written at parse time when it changed): changing one re-renders that entry only; touching a
# mesh re-runs its entry; a tool or a stage's parameters re-run what they feed.
.PHONY: user-modelbase
ifneq ($(filter user-modelbase,$(MAKECMDGOALS)),)
MESHES ?=
MESH_UNITS ?= m
MESH_UP ?= z
MESH_CROP_LENGTH ?=
MESH_UP_CHECK ?= refuse
$(if $(filter-out refuse warn off,$(MESH_UP_CHECK)),$(error user-modelbase: MESH_UP_CHECK=$(MESH_UP_CHECK): must be refuse, warn or off))
$(if $(filter 1,$(words $(MESH_UP_CHECK))),,$(error user-modelbase: MESH_UP_CHECK needs one value))
$(if $(filter-out mm cm m,$(MESH_UNITS)),$(error user-modelbase: MESH_UNITS=$(MESH_UNITS): must be mm, cm or m))
$(if $(filter-out y z,$(MESH_UP)),$(error user-modelbase: MESH_UP=$(MESH_UP): must be y or z))
$(if $(filter 2,$(words $(MESH_UNITS) $(MESH_UP))),,$(error user-modelbase: MESH_UNITS and MESH_UP need one value each))
$(if $(filter 0 1,$(words $(MESH_CROP_LENGTH))),,$(error user-modelbase: MESH_CROP_LENGTH=$(MESH_CROP_LENGTH): one length, e.g. 14m))
$(if $(MESH_CROP_LENGTH),$(if $(shell echo '$(MESH_CROP_LENGTH)' | grep -Ex '[0-9]+(\.[0-9]+)?(m|cm|mm)?'),,\
  $(error user-modelbase: MESH_CROP_LENGTH=$(MESH_CROP_LENGTH): a length such as 14m, 1400cm or 14000mm)))
# MODELBASE: given on the command line (Makefile.experiments' own MODELBASE is the thesis
# experiment's list of graphs), one directory.
$(if $(filter command line environment override,$(origin MODELBASE)),,$(error user-modelbase: give \
  MODELBASE=<directory for the entries> (created when missing)))
UMB := $(patsubst %/,%,$(MODELBASE))
$(if $(filter 1,$(words $(UMB))),,$(error user-modelbase: MODELBASE=$(MODELBASE): one directory))
$(if $(shell echo '$(UMB)' | grep -Ex '[A-Za-z0-9_./-]+'),,$(error user-modelbase: MODELBASE=$(UMB): \
  the path must be made of [A-Za-z0-9_./-]))
UMB_WORK := $(UMB)/.work
# NAME:FILE:CLASS words, sorted (scripts/usermb-list.sh; one shell per parse), or ERROR <message>.
UMB_LIST := $(shell scripts/usermb-list.sh '$(MESHES)')
$(if $(filter ERROR,$(firstword $(UMB_LIST))),$(error user-modelbase: $(wordlist 2,$(words $(UMB_LIST)),$(UMB_LIST))))
umb_name = $(word 1,$(subst :, ,$(1)))
umb_file = $(word 2,$(subst :, ,$(1)))
umb_class = $(filter-out -,$(word 3,$(subst :, ,$(1))))
$(foreach e,$(UMB_LIST),$(if $(call umb_class,$(e)),,$(warning user-modelbase: $(call umb_file,$(e)) has no \
  class (no <class>__ in its name, no row in $(MESHES)/classes.csv): $(UMB)/$(call umb_name,$(e)).class is not written)))
$(if $(filter meshsize,$(TOOLS)),,$(eval $(call tool_rule,meshsize)))

# The entries this make built before (they have import.txt), and the directory each came from
# (read here, before the rules below rewrite a changed import.txt); pruning: below.
# umb_built_from(name): the mesh file an entry was built from (import.txt's first line).
# umb_dir_key(path): a mesh file's directory by its real path, else as written.
umb_built_from = $(word 2,$(file <$(UMB_WORK)/$(1)/import.txt))
umb_dir_key = $(or $(realpath $(patsubst %/,%,$(dir $(1)))),$(patsubst %/,%,$(dir $(1))))
UMB_HERE := $(or $(realpath $(patsubst %/,%,$(MESHES))),$(patsubst %/,%,$(MESHES)))
UMB_BUILT := $(patsubst $(UMB_WORK)/%/import.txt,%,$(wildcard $(UMB_WORK)/*/import.txt))
UMB_NAMES := $(foreach e,$(UMB_LIST),$(call umb_name,$(e)))
# An entry of this directory's name built from another directory's mesh is rebuilt from this
# one (import.txt changes): said, since the other directory's entry is replaced.
$(foreach e,$(UMB_LIST),$(foreach n,$(call umb_name,$(e)),$(if $(filter $(n),$(UMB_BUILT)),$(foreach \
  o,$(call umb_built_from,$(n)),$(if $(filter $(UMB_HERE),$(call umb_dir_key,$(o))),,$(warning user-modelbase: \
  $(UMB)/$(n) was built from $(o), another MESHES directory: $(call umb_file,$(e)) replaces it))))))

# The work directories, for import.txt and class.txt: written at parse time when they changed
# (text_prereq, Makefile.experiments); a dry run writes nothing.
$(if $(dry_run),,$(shell mkdir -p $(foreach e,$(UMB_LIST),$(UMB_WORK)/$(call umb_name,$(e)))))

umb_import = mesh $(1)$(nl)units $(MESH_UNITS)$(nl)up $(MESH_UP)$(nl)crop-length $(or $(MESH_CROP_LENGTH),auto)
# umb_link(FROM, TO): a hard link (the tools replace files by renaming, so a link keeps the
# entry's bytes as a copy would), a copy where the filesystem has none.
umb_link = ln -f $(1) $(2) 2>/dev/null || cp $(1) $(2)
# umb_rule(name, file, FORCE when a dry run finds import.txt out of date): one entry's chain,
# its .json and .pcd. (The FORCE goes on the stages themselves: on import.txt, a target without a
# recipe, make 4.3 would not pass it on.)
define umb_rule
$(UMB_WORK)/$(1)/import.txt:
$(UMB_WORK)/$(1)/size.txt: $(2) $(UMB_WORK)/$(1)/import.txt $(3) $(call tool,meshsize)
	@$(STAGE) $$@ -- $(BIN)/meshsize --units $(MESH_UNITS) --up $(MESH_UP) --up-check $(MESH_UP_CHECK) \
	  -i $(2) -o $$@$(if $(filter warn,$(MESH_UP_CHECK)), && { grep -h '^meshsize: warning:' $$@.log >&2 || true; })
$(UMB_WORK)/$(1)/scan.pcd: $(2) $(UMB_WORK)/$(1)/size.txt $(UMB_WORK)/$(1)/import.txt $(3) $(call tool,rangetrace) \
    $(P)/rangetrace.ini share/scenes/unoccluded.scene scripts/usermb-crop.sh
	@crop=$$$$(scripts/usermb-crop.sh $(UMB_WORK)/$(1)/size.txt $(P)/rangetrace.ini $(MESH_CROP_LENGTH)) && \
	  $(STAGE) $$@ -- $(BIN)/rangetrace --config $(P)/rangetrace.ini --model $(2) --units $(MESH_UNITS) \
	  --up $(MESH_UP) $$$$crop --scene unoccluded --seed $$(call seed,user/$(1)) --threads 2 -o $$@
.SECONDARY: $(UMB_WORK)/$(1)/scan.pcd $(UMB_WORK)/$(1)/noise-0/scan.pcd
$(call noisy_rule,$(UMB_WORK)/$(1)/scan.pcd,$(UMB_WORK)/$(1)/noise-0/scan.pcd,0,user/$(1)/0,, && rm -f $$<)
$(UMB_WORK)/$(1)/noise-0/samples.pcd: $(UMB_WORK)/$(1)/noise-0/scan.pcd $(call tool,fitvox) $(P)/fitvox.ini
	@$(STAGE) $$@ -- $(BIN)/fitvox --config $(P)/fitvox.ini --pcd-encoding $(PCD_ENCODING) -i $$< -o $$@ && rm -f $$<
$(UMB_WORK)/$(1)/noise-0/mesh.ply: $(UMB_WORK)/$(1)/noise-0/samples.pcd $(call tool,cocone) $(P)/cocone.ini
	@$(STAGE) $$@ -- $(BIN)/cocone --config $(P)/cocone.ini -i $$< -o $$@
$(UMB_WORK)/$(1)/noise-0/segments.json: $(UMB_WORK)/$(1)/noise-0/mesh.ply $(call tool,ncut) $(P)/ncut.ini
	@$(STAGE) $$@ -- $(BIN)/ncut --config $(P)/ncut.ini --seed $$(call seed,user/$(1)/0) -i $$< \
	  -o $$@ --colored $(UMB_WORK)/$(1)/noise-0/segments.ply
$(UMB)/$(1).json: $(UMB_WORK)/$(1)/noise-0/segments.json
	@$(call umb_link,$$<,$(UMB)/.$(1).tmp$$$$$$$$.json) && mv $(UMB)/.$(1).tmp$$$$$$$$.json $$@ && echo "done  $$@"
$(UMB)/$(1).pcd: $(UMB_WORK)/$(1)/noise-0/samples.pcd | $(UMB_WORK)/$(1)/noise-0/segments.json
	@$(call umb_link,$$<,$(UMB)/.$(1).tmp$$$$$$$$.pcd) && mv $(UMB)/.$(1).tmp$$$$$$$$.pcd $$@ && echo "done  $$@"
endef
# umb_class_rule(name, FORCE or nothing as above): its .class, from the class written at parse
# time when it changed.
define umb_class_rule
$(UMB_WORK)/$(1)/class.txt:
$(UMB)/$(1).class: $(UMB_WORK)/$(1)/class.txt $(2)
	@cp $$< $(UMB)/.$(1).tmp$$$$$$$$.class && mv $(UMB)/.$(1).tmp$$$$$$$$.class $$@ && echo "done  $$@"
endef
$(foreach e,$(UMB_LIST),$(foreach n,$(call umb_name,$(e)),$(eval $(call umb_rule,$(n),$(call umb_file,$(e)),\
  $(call text_prereq,$(UMB_WORK)/$(n)/import.txt,$(call umb_import,$(call umb_file,$(e))))))))
$(foreach e,$(UMB_LIST),$(foreach n,$(call umb_name,$(e)),$(if $(call umb_class,$(e)),$(eval $(call umb_class_rule,$(n),\
  $(call text_prereq,$(UMB_WORK)/$(n)/class.txt,$(call umb_class,$(e))))))))
# The window (as FAM_MB_WINDOW in mk/families.mk): entry i's render waits for entry
# i - UMB_WINDOW to be done (an order-only prerequisite), so at most UMB_WINDOW entries'
# scans (15-80 MB) are on disk at once. Keep it >= the -j count; 0 = no window.
UMB_WINDOW ?= 4
$(if $(shell echo '$(UMB_WINDOW)' | grep -Ex '[0-9]+'),,$(error user-modelbase: UMB_WINDOW=$(UMB_WINDOW): a whole number >= 0))
UMB_WAITS := $(if $(and $(filter-out 0,$(UMB_WINDOW)),$(word $(UMB_WINDOW),$(wordlist 2,$(words $(UMB_NAMES)),$(UMB_NAMES)))),$(shell printf '%s\n' \
  $(UMB_NAMES) | awk -v w='$(UMB_WINDOW)' '{ id[NR] = $$0 } NR > w { print $$0 ":" id[NR - w] }'))
$(foreach p,$(UMB_WAITS),$(eval $(UMB_WORK)/$(firstword $(subst :, ,$(p)))/scan.pcd: | \
  $(UMB_WORK)/$(lastword $(subst :, ,$(p)))/noise-0/segments.json))
# An entry this make built (MODELBASE/.work/<name>/import.txt) from this MESHES directory whose
# mesh has left it is removed (its .json, .pcd, .class and work directory), and so is the .class
# of an entry that no longer has a class, so the modelbase matches the meshes. Entries built from
# another MESHES directory (import.txt's "mesh" line names the file: its directory, by real path,
# or as written when it is gone) are kept: several runs with different MESHES, MESH_UNITS and
# MESH_UP build one modelbase (stop 71, review F8: a second directory's run removed the first's
# entries, saying "mesh gone from <the second>"). Entries not built here are never touched. A
# dry run removes nothing: it prints what would go (-q: out of date).
UMB_GONE := $(foreach n,$(filter-out $(UMB_NAMES),$(UMB_BUILT)),$(if $(filter $(UMB_HERE),$(call \
  umb_dir_key,$(call umb_built_from,$(n)))),$(n)))
UMB_GONE_FILES := $(wildcard $(foreach n,$(UMB_GONE),$(UMB_WORK)/$(n) $(UMB)/$(n).json $(UMB)/$(n).pcd $(UMB)/$(n).class))
UMB_UNCLASSED := $(wildcard $(foreach e,$(UMB_LIST),$(if $(call umb_class,$(e)),,$(UMB)/$(call \
  umb_name,$(e)).class $(UMB_WORK)/$(call umb_name,$(e))/class.txt)))
UMB_PRUNE := $(UMB_GONE_FILES) $(UMB_UNCLASSED)
ifneq ($(strip $(UMB_PRUNE)),)
ifneq ($(dry_run),)
user-modelbase: $(UMB_WORK)/.prune
$(UMB_WORK)/.prune:
	@echo "user-modelbase: would remove $(strip $(UMB_PRUNE))"
else
$(if $(UMB_GONE_FILES),$(info user-modelbase: removing $(UMB_GONE_FILES) (mesh gone from $(MESHES))))
$(if $(UMB_UNCLASSED),$(info user-modelbase: removing $(UMB_UNCLASSED) (the mesh has no class any more)))
$(shell rm -rf $(UMB_PRUNE))
endif
endif
user-modelbase: $(foreach e,$(UMB_LIST),$(foreach n,$(call umb_name,$(e)),$(UMB)/$(n).json $(UMB)/$(n).pcd \
  $(if $(call umb_class,$(e)),$(UMB)/$(n).class)))
endif
