/* hand.c — parameters as a person sets them (bbcgen's command line, its
 * prompt, the session): a value set by hand is meant, so a texres set by
 * hand turns atlasmax off and an epsilon turns maxplanes and minplanes off,
 * unless those are set by hand too. */
#include "app.h"

#include <assert.h>
#include <string.h>
#include <strings.h>

/* A parameter's bit in bbc_hand: its index in the table. */
static long row_index(const char *name) {
  assert(bbc_param_count() <= 64); /* a bit per parameter */
  for (size_t i = 0; i < bbc_param_count(); i++)
    if (!strcasecmp(bbc_param_at(i)->name, name)) return (long)i;
  return -1;
}

int bbc_params_by_hand(bbc_hand hand, const char *name) {
  long i = row_index(name);
  return i >= 0 && ((hand >> i) & 1u);
}

void bbc_params_note_hand(bbc_params *p, bbc_hand *hand, const char *name) {
  long i = row_index(name);
  if (i >= 0) *hand |= (bbc_hand)1 << i;
  if (bbc_params_by_hand(*hand, "texres") && !bbc_params_by_hand(*hand, "atlasmax"))
    p->atlas_max = 0;
  if (bbc_params_by_hand(*hand, "epsilon") && !bbc_params_by_hand(*hand, "maxplanes"))
    p->max_planes = 0;
  if (bbc_params_by_hand(*hand, "epsilon") && !bbc_params_by_hand(*hand, "minplanes"))
    p->min_planes = 0;
}

bbc_result bbc_params_set_by_hand(bbc_params *p, bbc_hand *hand, const char *name, const char *text,
                                  bbc_error *err) {
  bbc_result r = bbc_params_set(p, name, text, err);
  if (r == BBC_OK) bbc_params_note_hand(p, hand, name);
  return r;
}

void bbc_params_thesis_merge(bbc_params *p, bbc_hand hand) {
  bbc_params t;
  bbc_params_thesis(&t);
  for (size_t i = 0; i < bbc_param_count(); i++)
    if (!((hand >> i) & 1u)) bbc_params_copy(p, &t, bbc_param_at(i));
  /* the rules still hold for what was set by hand */
  bbc_params_note_hand(p, &hand, "");
}

void bbc_params_lod_chain(bbc_params *p, bbc_hand hand) {
  if (!bbc_params_by_hand(hand, "maxplanes")) p->max_planes = 0;
  if (!bbc_params_by_hand(hand, "minplanes")) p->min_planes = 0;
}

void bbc_params_lighting(bbc_params *p, bbc_hand hand, bbc_lighting mode) {
  int baked = mode == BBC_LIGHTING_BAKED;
  if (!bbc_params_by_hand(hand, "prelight")) p->prelight = baked;
  if (!bbc_params_by_hand(hand, "nm")) p->normal_maps = !baked;
  if (!bbc_params_by_hand(hand, "occlusion")) p->occlusion = baked ? 0 : 64;
  if (!bbc_params_by_hand(hand, "unlit")) p->unlit = BBC_UNLIT_WHEN_PRELIT;
}

bbc_lighting bbc_lighting_for_output(const char *path) {
  size_t n = path ? strlen(path) : 0;
  int gltf = (n >= 4 && !strcasecmp(path + n - 4, ".glb")) ||
             (n >= 5 && !strcasecmp(path + n - 5, ".gltf")) ||
             (n >= 4 && !strcasecmp(path + n - 4, ".fbx")); /* lit by engines too */
  return gltf ? BBC_LIGHTING_MATERIAL : BBC_LIGHTING_BAKED;
}

const char *bbc_params_lighting_name(const bbc_params *p) {
  if (p->prelight) return bbc_params_is_unlit(p) ? "baked" : "baked, lit again";
  if (bbc_params_is_unlit(p)) return "albedo, unlit";
  return p->normal_maps ? (p->occlusion > 0 ? "material" : "material without occlusion")
                        : "material without normal maps";
}
