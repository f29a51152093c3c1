# convert.mk — convert a folder of models into Billboard Clouds with bbcgen,
# one bbcgen run per model, as many at a time as make's -j allows.
#
#   make -f scripts/tools/convert.mk IN=models/ OUT=clouds/ [-j N] [-k]
#        [BBCGEN=path] [ARGS="--epsilon 8 ..."] [EXT=glb] [REPORT=0]
#        [MODEL_EXTS="obj 3ds glb gltf fbx dae ply off"]
#   make -f scripts/tools/convert.mk IN=... OUT=... list   # models and their outputs
#
# Every model under IN (subfolders too) whose extension is in MODEL_EXTS, in
# any case (tree.obj, TREE.OBJ), gives OUT/<same subfolder>/<name>.EXT and,
# unless REPORT=0, the report OUT/<subfolder>/<name>.json. An output depends
# on its model and on the .mtl beside it with the same name (tree.obj ->
# tree.mtl), so a second run converts nothing ("Nothing to be done for
# 'all'") and a changed model or material is converted again. Not tracked:
# textures, a .mtl with another name, the bbcgen binary, ARGS; use -B (or
# delete the outputs) after changing those.
#
# A model bbcgen fails on stops make (make exits 2) after the line
#     convert: FAILED models/x.obj (bbcgen exit 4)
# on stderr, with bbcgen's status (1 usage ... 7 interrupted, see docs/cli.md); its
# output and report are removed, so no output is left older than or other
# than its model. Jobs already running finish; -k converts all the others.
#
# Threads: with -jN each bbcgen gets cores/N OpenMP threads (at least 1;
# 1 with -j alone), not all cores each; OMP_NUM_THREADS or ARGS="--threads
# K" overrides. Models start largest file first.
#
# Known make limitation: model paths with whitespace or any of
#     : # % = ; | ( ) * ? [ ] $ \ ' "
# cannot be make targets; such a name stops make with a message naming it
# (rename it, or use scripts/tools/convert_parallel.sh, which takes any name).
# Two models that would write the same output (tree.obj and tree.3ds in one
# folder) stop make too. See docs/batch.md.

convert_mk_dir := $(dir $(abspath $(lastword $(MAKEFILE_LIST))))

SHELL := /bin/bash
.SUFFIXES:
MAKEFLAGS += --no-builtin-rules
.DEFAULT_GOAL := all
.DELETE_ON_ERROR:
.PHONY: all list

EXT ?= glb
REPORT ?= 1
MODEL_EXTS ?= obj 3ds glb gltf fbx dae ply off
# The build's tool beside this file, else bbcgen on PATH.
BBCGEN ?= $(firstword $(wildcard $(abspath $(convert_mk_dir)../../build/bin/bbcgen)) bbcgen)

convert_usage := usage: make -f scripts/tools/convert.mk IN=models/ OUT=clouds/ [-j N] [-k] [BBCGEN=path] [ARGS="..."] [EXT=glb] [REPORT=0]
ifneq ($(words $(IN)) $(words $(OUT)),1 1)
  $(error $(convert_usage) (IN and OUT: one folder each, no spaces))
endif
# models/ and models// -> models (but / stays /).
convert_trim = $(if $(filter-out /,$(1)),$(patsubst %/,%,$(patsubst %/,%,$(1))),$(1))
override IN := $(call convert_trim,$(IN))
override OUT := $(call convert_trim,$(OUT))
ifeq ($(wildcard $(IN)/.),)
  $(error convert.mk: IN=$(IN) is not a folder)
endif
ifeq ($(shell command -v $(firstword $(BBCGEN))),)
  $(error convert.mk: bbcgen not found: BBCGEN=$(BBCGEN) (build it, put it on PATH or pass BBCGEN=path))
endif

# The models, largest file first (make -j then starts the longest
# conversions first rather than ending on one big model alone), then //OK//
# when find succeeded; a name make cannot take is reported on stderr and adds
# the word //BAD//. ($(shell) joins the lines of its command: semicolons.)
define convert_scan
set -o pipefail; find -L '$(IN)' -type f \( $(foreach e,$(MODEL_EXTS),-iname '*.$(e)' -o) -false \) -printf '%s %p\n' |
LC_ALL=C sort -k1,1nr -k2 | cut -d' ' -f2- | {
  bad=0;
  while IFS= read -r f; do
    case $$f in
      *[][[:space:]:#%=\;\|\(\)\*\?\$$\\\'\"]*)
        printf 'convert.mk: cannot take this model name in make: %s\n' "$$f" >&2; bad=1 ;;
      *) printf '%s\n' "$$f" ;;
    esac;
  done;
  if [ $$bad = 1 ]; then echo //BAD//; fi;
} && echo //OK//
endef
convert_found := $(shell $(convert_scan))
ifeq ($(filter //OK//,$(convert_found)),)
  $(error convert.mk: could not list the models in $(IN))
endif
convert_found := $(filter-out //OK//,$(convert_found))
ifneq ($(filter //BAD//,$(convert_found)),)
  $(error convert.mk: rename the model(s) above (whitespace or : # % = ; | ( ) * ? [ ] $$ \ ' " in the path) or use scripts/tools/convert_parallel.sh)
endif
# Never take our own outputs as models (OUT inside IN).
convert_out_abs := $(abspath $(OUT))
MODELS := $(foreach m,$(convert_found),$(if $(filter $(convert_out_abs)/%,$(abspath $(m))),,$(m)))

# models/sub/Tree.OBJ -> clouds/sub/Tree.glb
convert_out_of = $(OUT)/$(patsubst $(IN)/%,%,$(basename $(1))).$(EXT)
OUTPUTS := $(foreach m,$(MODELS),$(call convert_out_of,$(m)))

ifneq ($(words $(OUTPUTS)),$(words $(sort $(OUTPUTS))))
  $(error convert.mk: two models would write the same output: $(shell printf '%s\n' $(OUTPUTS) | LC_ALL=C sort | uniq -d | tr '\n' ' ')(rename one))
endif
ifeq ($(MODELS),)
  $(warning convert.mk: no models ($(MODEL_EXTS)) found in $(IN))
endif

convert_report = $(if $(filter-out 0 no,$(REPORT)),--report '$(basename $@).json')

# Threads per bbcgen: with -jN, cores/N (at least 1), so that N jobs of
# all-core OpenMP teams do not fight over the cores; with -j (no limit) 1;
# without -j bbcgen's default (all cores). OMP_NUM_THREADS set by the caller,
# or --threads in ARGS, wins. (-j shows in MAKEFLAGS only inside recipes.)
convert_nproc := $(shell nproc 2>/dev/null || echo 1)
convert_jobs = $(patsubst -j%,%,$(filter -j%,$(MAKEFLAGS)))
convert_threads = $(if $(OMP_NUM_THREADS),,$(if $(filter -j,$(MAKEFLAGS)),1,$(if \
  $(convert_jobs),$(shell n=$$(( $(convert_nproc) / $(convert_jobs) )); echo $$(( n > 0 ? n : 1 ))))))
convert_env = $(if $(convert_threads),OMP_NUM_THREADS=$(convert_threads) )

define convert_recipe
@mkdir -p '$(@D)'
@echo 'convert: $<'
@rc=0; $(convert_env)$(BBCGEN) '$<' -o '$@' $(convert_report) -q $(ARGS) || rc=$$?; \
if [ $$rc -ne 0 ]; then \
  rm -f '$@' '$(basename $@).json'; \
  echo "convert: FAILED $< (bbcgen exit $$rc)" >&2; exit $$rc; \
fi
endef

# One rule per model: OUTPUT: MODEL [its .mtl]
define convert_rule
$(convert_o): $(m) $(wildcard $(basename $(m)).mtl $(basename $(m)).MTL)
	$$(convert_recipe)
endef
$(foreach m,$(MODELS),$(eval convert_o := $(call convert_out_of,$(m)))$(eval $(convert_rule)))

all: $(OUTPUTS)

list:
	@:$(foreach m,$(MODELS),$(info $(m) -> $(call convert_out_of,$(m))))
