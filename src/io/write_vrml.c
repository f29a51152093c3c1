/* write_vrml.c — a Billboard Cloud as VRML (thesis Appendix A, "save"): the
 * .wrl and beside it the colour atlas <stem>_wrl_<material>.png (and the normal atlas
 * ..._nm.png in format 0; with the dds option the colour atlas also as .dds with
 * its mip levels), every file atomic. The whole text is built in memory
 * first, then the PNGs are written, then the .wrl, so a failure writes
 * nothing and the .wrl never names a missing file. */
#include "io.h"

#include <stdio.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the text: io's buffer ------------------------------------------------ */

/* `s` without line ends and other control characters (comment text). */
static void put_line_text(bbc__text *t, const char *s, size_t n) {
  for (size_t i = 0; i < n; i++) {
    unsigned char c = (unsigned char)s[i];
    bbc__text_printf(t, "%c", c < 0x20 && c != '\t' ? ' ' : (char)c);
  }
}

/* A quoted relative URL naming <stem><suffix>: bytes outside RFC 3986's
 * unreserved and sub-delimiter characters are percent-encoded, so the
 * VRML string needs no escapes. */
static void put_url(bbc__text *t, const char *stem, const char *suffix) {
  bbc__text_printf(t, "\"");
  for (int part = 0; part < 2; part++)
    for (const char *p = part ? suffix : stem; *p; p++) {
      unsigned char c = (unsigned char)*p;
      int safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 (c && strchr("-._~!$&'()*+,;=@", c));
      if (safe)
        bbc__text_printf(t, "%c", (char)c);
      else
        bbc__text_printf(t, "%%%02X", c);
    }
  bbc__text_printf(t, "\"");
}

/* ---- the file -------------------------------------------------------------- */

typedef struct vrml_ctx {
  const bbc_mesh *m;
  const char *stem;
  char col_suffix[200], nm_suffix[200]; /* "_<material>.png", "_<material>_nm.png" */
  char dds_suffix[200];                 /* "_<material>.dds", "" without DDS */
  int unlit;                            /* no Material: the (prelit) texture shown as it is */
  int nm_nodes; /* format 0 with normal maps: a NormalMap node beside each Shape */
  int solid;    /* one-sided copies (back images) */
} vrml_ctx;

/* How many of triangles [t0, t0 + n - 2) are the fan of vertices
 * [base, base + n), wound as the front (back = 0) or the back (back = 1), in
 * order: fewer than n - 2 when the mesh dropped a zero-area triangle of a
 * degenerate outline (its polygon is still written whole). */
static size_t fan_count(const bbc_mesh *m, size_t base, size_t t0, int n, int back) {
  size_t t = t0;
  for (int c = 1; c + 1 < n && t < m->triangle_count; c++) {
    const uint32_t *ix = m->indices + 3 * t;
    size_t b1 = base + (size_t)c, b2 = b1 + 1;
    if (ix[0] == base && ix[1] == (back ? b2 : b1) && ix[2] == (back ? b1 : b2)) t++;
  }
  return t - t0;
}

/* A Shape's appearance, indented by `in`: the atlas (the DDS with its mip
 * levels first when there is one, the PNG for the rest), a white Material
 * unless unlit (VRML97 6.4: an Appearance without a material is drawn
 * unlit). */
static void put_appearance(bbc__text *t, const vrml_ctx *x, const char *in) {
  bbc__text_printf(t, "%s  appearance Appearance {\n", in);
  if (!x->unlit) bbc__text_printf(t, "%s    material Material { diffuseColor 1 1 1 }\n", in);
  bbc__text_printf(t, "%s    texture ImageTexture { url ", in);
  if (x->dds_suffix[0]) {
    bbc__text_printf(t, "[ ");
    put_url(t, x->stem, x->dds_suffix);
    bbc__text_printf(t, " ");
    put_url(t, x->stem, x->col_suffix);
    bbc__text_printf(t, " ]");
  } else {
    put_url(t, x->stem, x->col_suffix);
  }
  bbc__text_printf(t, " repeatS FALSE repeatT FALSE }\n");
  bbc__text_printf(t, "%s  }\n", in);
}

/* Vectors [from, to) of d (or, NULL, f), 3 each, one a line. */
static void put_vectors(bbc__text *t, const double *d, const float *f, size_t from, size_t to,
                        int digits) {
  for (size_t v = from; v < to; v++) {
    bbc__text_printf(t, "      ");
    for (int j = 0; j < 3; j++) {
      if (j) bbc__text_printf(t, " ");
      bbc__text_number(t, digits, d ? d[3 * v + j] : f[3 * v + j]);
    }
    bbc__text_printf(t, "%s\n", v + 1 < to ? "," : "");
  }
}

/* The limbs' mesh (`limbs`): vertices from v0 on, triangles from t0 on,
 * smooth normals, every corner on the swatch of their colour in the atlas. */
static void put_limbs(bbc__text *t, const vrml_ctx *x, size_t v0, size_t t0) {
  const bbc_mesh *m = x->m;
  bbc__text_printf(t, "\n# the trunk part as a mesh (limbs): %zu triangles\n",
                   m->triangle_count - t0);
  bbc__text_printf(t, "DEF Limbs Shape {\n");
  put_appearance(t, x, "");
  bbc__text_printf(t, "  geometry IndexedFaceSet {\n    ccw TRUE\n    solid FALSE\n");
  bbc__text_printf(t, "    coord Coordinate { point [\n");
  put_vectors(t, m->positions, NULL, v0, m->vertex_count, 9);
  bbc__text_printf(t, "    ] }\n");
  if (m->normals) {
    bbc__text_printf(t, "    normal Normal { vector [\n");
    put_vectors(t, NULL, m->normals, v0, m->vertex_count, 6);
    bbc__text_printf(t, "    ] }\n");
  }
  bbc__text_printf(t, "    texCoord TextureCoordinate { point [ ");
  bbc__text_number(t, 7, m->uvs[2 * v0]);
  bbc__text_printf(t, " ");
  bbc__text_number(t, 7, m->uvs[2 * v0 + 1]);
  bbc__text_printf(t, " ] }\n    coordIndex [\n");
  for (size_t i = t0; i < m->triangle_count; i++) {
    const uint32_t *ix = m->indices + 3 * i;
    bbc__text_printf(t, "      %zu %zu %zu -1%s\n", (size_t)(ix[0] - v0), (size_t)(ix[1] - v0),
                     (size_t)(ix[2] - v0), i + 1 < m->triangle_count ? "," : "");
  }
  bbc__text_printf(t, "    ]\n    texCoordIndex [\n");
  for (size_t i = t0; i < m->triangle_count; i++)
    bbc__text_printf(t, "      0 0 0 -1%s\n", i + 1 < m->triangle_count ? "," : "");
  bbc__text_printf(t, "    ]\n  }\n}\n");
}

/* One side of billboard k: vertices [base, base + n) of the mesh. */
static void put_side(bbc__text *t, const vrml_ctx *x, size_t k, int back, size_t base, int n) {
  const char *in = x->nm_nodes ? "  " : ""; /* inside the Group */
  if (x->nm_nodes) bbc__text_printf(t, "Group { children [\n");
  bbc__text_printf(t, "%sDEF BB%zu_%s Shape {\n", in, k, back ? "back" : "front");
  put_appearance(t, x, in);
  bbc__text_printf(t, "%s  geometry IndexedFaceSet {\n", in);
  bbc__text_printf(t, "%s    ccw TRUE\n", in);
  bbc__text_printf(t, "%s    solid %s\n", in, x->solid ? "TRUE" : "FALSE");
  bbc__text_printf(t, "%s    coord Coordinate { point [\n", in);
  for (int c = 0; c < n; c++) {
    const double *p = x->m->positions + 3 * (base + (size_t)c);
    bbc__text_printf(t, "%s      ", in);
    for (int j = 0; j < 3; j++) {
      if (j) bbc__text_printf(t, " ");
      bbc__text_number(t, 9, p[j]);
    }
    bbc__text_printf(t, "%s\n", c + 1 < n ? "," : "");
  }
  bbc__text_printf(t, "%s    ] }\n", in);
  bbc__text_printf(t, "%s    texCoord TextureCoordinate { point [\n", in);
  for (int c = 0; c < n; c++) {
    const float *uv = x->m->uvs + 2 * (base + (size_t)c);
    bbc__text_printf(t, "%s      ", in);
    bbc__text_number(t, 7, uv[0]);
    bbc__text_printf(t, " ");
    bbc__text_number(t, 7, uv[1]);
    bbc__text_printf(t, "%s\n", c + 1 < n ? "," : "");
  }
  bbc__text_printf(t, "%s    ] }\n", in);
  /* The order the triangles wind: 0..n-1 for the front, n-1..0 for the back. */
  bbc__text_printf(t, "%s    coordIndex [", in);
  for (int c = 0; c < n; c++) bbc__text_printf(t, " %d", back ? n - 1 - c : c);
  bbc__text_printf(t, " -1 ]\n");
  bbc__text_printf(t, "%s  }\n", in);
  bbc__text_printf(t, "%s}\n", in);
  if (x->nm_nodes) {
    bbc__text_printf(t, "  NormalMap { url ");
    put_url(t, x->stem, x->nm_suffix);
    bbc__text_printf(t, " }\n] }\n");
  }
}

/* The request: a NAME.wrl path, a cloud, and format 0 or 1. */
static bbc_result check_request(const char *wrl_path, const bbc_cloud *cloud, int format,
                                bbc_error *err) {
  if (!wrl_path || !cloud)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "VRML output: no path or no cloud");
  char ext[8];
  bbc__path_extension(wrl_path, ext, sizeof ext);
  const char *base_name = strrchr(wrl_path, '/') ? strrchr(wrl_path, '/') + 1 : wrl_path;
  if (strcmp(ext, "wrl") || strlen(base_name) <= 4)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: VRML output must be NAME.wrl", wrl_path);
  if (format != BBC_VRML_EXTENDED && format != BBC_VRML_97)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "%s: VRML format must be 0 (VRML 2.0 with extensions) or 1 (VRML97), not %d",
                     wrl_path, format);
  return BBC_OK;
}

/* The cloud has billboards and a mesh with its colour atlas, and the normal
 * atlas when its material names one; *nm is that normal atlas when the
 * format writes it (format 0), else NULL. */
static bbc_result check_atlases(const char *wrl_path, const bbc_cloud *cloud, int format,
                                const bbc_image **nm, bbc_error *err) {
  const bbc_mesh *m = &cloud->mesh;
  if (cloud->billboard_count == 0 || !cloud->billboards)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: the cloud has no billboards", wrl_path);
  if (m->texture_count < 1 || !m->textures || !m->textures[0].image.rgba || !m->positions ||
      !m->uvs || !m->indices || m->material_count < 1 || !m->materials)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "%s: the cloud has no mesh with a colour atlas", wrl_path);
  const bbc_material *mat = &m->materials[0];
  *nm = NULL;
  if (mat->normal_map == 2) {
    if (m->texture_count < 2 || !m->textures[1].image.rgba)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: the cloud's normal atlas is missing",
                       wrl_path);
    *nm = &m->textures[1].image;
  }
  if (format == BBC_VRML_97) *nm = NULL; /* VRML97: no normal maps */
  return BBC_OK;
}

/* The mesh must hold, per billboard and side, its outline's fan, then the
 * limbs' mesh (`limbs`): the remaining triangles, on the remaining
 * vertices. *fan_triangles: the triangles of the fans. */
static bbc_result check_layout(const char *wrl_path, const bbc_cloud *cloud, int sides,
                               size_t *fan_triangles, bbc_error *err) {
  const bbc_mesh *m = &cloud->mesh;
  size_t nv = 0, nt = 0;
  for (size_t k = 0; k < cloud->billboard_count; k++) {
    int n = cloud->billboards[k].corner_count;
    if (n < 3 || n > 10)
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY, "%s: billboard %zu has %d corners",
                       wrl_path, k, n);
    for (int side = 0; side < sides; side++) {
      /* A degenerate outline may have lost all its triangles; a mesh that
       * is not the cloud's is caught by the count after the loop. */
      if (nv + (size_t)n > m->vertex_count)
        return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                         "%s: the cloud's mesh does not match billboard %zu", wrl_path, k);
      for (size_t v = nv; v < nv + (size_t)n; v++)
        if (!isfinite(m->positions[3 * v]) || !isfinite(m->positions[3 * v + 1]) ||
            !isfinite(m->positions[3 * v + 2]) || !isfinite(m->uvs[2 * v]) ||
            !isfinite(m->uvs[2 * v + 1]))
          return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                           "%s: billboard %zu has a non-finite coordinate", wrl_path, k);
      nt += fan_count(m, nv, nt, n, side);
      nv += (size_t)n;
    }
  }
  for (size_t i = 3 * nt; i < 3 * m->triangle_count; i++)
    if (m->indices[i] < nv || m->indices[i] >= m->vertex_count)
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                       "%s: the cloud's limbs use a billboard's vertex", wrl_path);
  for (size_t v = nv; v < m->vertex_count; v++)
    for (int j = 0; j < 3; j++)
      if (!isfinite(m->positions[3 * v + j]) || (j < 2 && !isfinite(m->uvs[2 * v + j])) ||
          (m->normals && !isfinite(m->normals[3 * v + j])))
        return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                         "%s: the cloud's limbs have a non-finite coordinate", wrl_path);
  if (m->triangle_count - nt != cloud->limb_triangles ||
      (cloud->limb_triangles == 0) != (m->vertex_count == nv))
    return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                     "%s: the cloud's mesh has more than its billboards", wrl_path);
  *fan_triangles = nt;
  return BBC_OK;
}

/* The header comments: what the file is, the caller's comment (each line
 * a comment), the format, the sides and the atlases. */
static void put_header(bbc__text *t, const bbc_cloud *cloud, const char *comment, int format,
                       int sides, const bbc_image *nm, int unlit) {
  const bbc_mesh *m = &cloud->mesh;
  bbc__text_printf(t, "#VRML V2.0 utf8\n");
  bbc__text_printf(t,
                   "# Billboard Cloud: %zu billboards, written by bbcgen " BBC_VERSION_STRING "\n",
                   cloud->billboard_count);
  for (const char *p = comment; p && *p;) {
    size_t n = strcspn(p, "\r\n");
    bbc__text_printf(t, n ? "# " : "#");
    put_line_text(t, p, n);
    bbc__text_printf(t, "\n");
    p += n;
    if (*p == '\r' && p[1] == '\n') p++;
    if (*p) p++;
  }
  bbc__text_printf(t, "# format %d (%s); %s; atlas %dx%d%s%s\n", format,
                   format ? "VRML97" : "VRML 2.0 with extensions",
                   sides == 2 ? "front and back images, one-sided" : "one image, double-sided",
                   m->textures[0].image.width, m->textures[0].image.height,
                   nm ? ", normal atlas" : "",
                   unlit ? "; unlit (no Material: the textures carry the light)" : "");
}

/* The Shapes' common settings and the atlases' file name suffixes. */
static void init_ctx(vrml_ctx *x, const bbc_mesh *m, const char *stem, int format, int unlit,
                     int dds, const bbc_image *nm, int sides) {
  memset(x, 0, sizeof *x);
  x->m = m;
  x->stem = stem;
  x->unlit = unlit;
  x->nm_nodes = format == BBC_VRML_EXTENDED && nm;
  x->solid = sides == 2;
  char name[160];
  bbc_texture_file_name(m, 0, name, sizeof name);
  snprintf(x->col_suffix, sizeof x->col_suffix, "_%s.png", name);
  if (dds && bbc_image_has_transparency(&m->textures[0].image))
    snprintf(x->dds_suffix, sizeof x->dds_suffix, "_%s.dds", name);
  bbc_texture_file_name(m, 1, name, sizeof name);
  snprintf(x->nm_suffix, sizeof x->nm_suffix, "_%s.png", name);
}

/* Every billboard's sides, in order; returns the vertices they take. */
static size_t put_billboards(bbc__text *t, const vrml_ctx *x, const bbc_cloud *cloud, int sides) {
  const bbc_mesh *m = x->m;
  size_t v = 0;
  for (size_t k = 0; k < cloud->billboard_count; k++) {
    const bbc_cloud_billboard *b = &cloud->billboards[k];
    bbc__text_printf(t, "\n# billboard %zu: %s plane, part %u", k, bbc_plane_kind_name(b->kind),
                     (unsigned)b->part);
    if (b->part < m->group_count && m->group_names && m->group_names[b->part]) {
      const char *g = m->group_names[b->part];
      bbc__text_printf(t, " (");
      put_line_text(t, g, strlen(g));
      bbc__text_printf(t, ")");
    }
    bbc__text_printf(t, ", %d corners\n", b->corner_count);
    for (int side = 0; side < sides; side++) {
      put_side(t, x, k, side, v, b->corner_count);
      v += (size_t)b->corner_count;
    }
  }
  return v;
}

/* The images first (DDS, PNGs), the .wrl last; a failed write leaves none
 * of its images behind. `png` (png_size bytes) holds each image's path. */
static bbc_result write_files(const char *wrl_path, const char *dir, char *png, size_t png_size,
                              const vrml_ctx *x, const bbc_image *nm, const bbc__text *t,
                              bbc_error *err) {
  const bbc_mesh *m = x->m;
  const char *stem = x->stem;
  bbc_result r = BBC_OK;
  int dds_written = 0;
  if (x->dds_suffix[0]) {
    snprintf(png, png_size, "%s%s%s", dir, stem, x->dds_suffix);
    r = bbc_image_write_dds(png, &m->textures[0].image, err);
    dds_written = r == BBC_OK;
  }
  int written = 0;
  if (r == BBC_OK) {
    snprintf(png, png_size, "%s%s%s", dir, stem, x->col_suffix);
    r = bbc_image_write_png(png, &m->textures[0].image, err);
    written = r == BBC_OK;
  }
  if (r == BBC_OK && nm) {
    snprintf(png, png_size, "%s%s%s", dir, stem, x->nm_suffix);
    r = bbc_image_write_png(png, nm, err);
    written += r == BBC_OK;
  }
  if (r == BBC_OK) r = bbc_write_file_atomic(wrl_path, t->data, t->size, err);
  if (r != BBC_OK) {
    if (dds_written) {
      snprintf(png, png_size, "%s%s%s", dir, stem, x->dds_suffix);
      remove(png);
    }
    if (written >= 1) {
      snprintf(png, png_size, "%s%s%s", dir, stem, x->col_suffix);
      remove(png);
    }
    if (written >= 2) {
      snprintf(png, png_size, "%s%s%s", dir, stem, x->nm_suffix);
      remove(png);
    }
  }
  return r;
}

bbc_result bbc_cloud_write_vrml(const char *wrl_path, const bbc_cloud *cloud,
                                const bbc_vrml_options *options, bbc_error *err) {
  int format = options ? (int)options->format : 0;
  int unlit = options ? options->unlit != 0 : 0, dds = options ? options->dds != 0 : 0;
  const char *comment = options ? options->comment : NULL;
  bbc_result r = check_request(wrl_path, cloud, format, err);
  if (r != BBC_OK) return r;
  const bbc_mesh *m = &cloud->mesh;
  const bbc_image *nm = NULL;
  r = check_atlases(wrl_path, cloud, format, &nm, err);
  if (r != BBC_OK) return r;
  int sides = m->materials[0].single_sided ? 2 : 1;
  size_t nt = 0;
  r = check_layout(wrl_path, cloud, sides, &nt, err);
  if (r != BBC_OK) return r;

  const char *base_name = strrchr(wrl_path, '/') ? strrchr(wrl_path, '/') + 1 : wrl_path;
  size_t len = strlen(wrl_path), stem_len = strlen(base_name);
  char *dir = malloc(len + 1), *stem = malloc(stem_len + 1), *png = malloc(len + 200);
  bbc__text t = {0};
  if (!dir || !stem || !png) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", wrl_path);
    goto done;
  }
  bbc__path_folder(wrl_path, dir, len + 1);
  bbc__side_file_stem(wrl_path, 0, stem, stem_len + 1); /* "t.wrl": t_wrl_billboards.png */

  put_header(&t, cloud, comment, format, sides, nm, unlit);
  vrml_ctx x;
  init_ctx(&x, m, stem, format, unlit, dds, nm, sides);
  if (x.nm_nodes) {
    bbc__text_printf(
        &t, "# NormalMap: the normal atlas (tangent space) of the Shape beside it; a no-op\n"
            "# for VRML97 readers.\n");
    bbc__text_printf(&t, "PROTO NormalMap [ exposedField MFString url [] ] { Group { } }\n");
  }
  /* Billboards, then the limbs. */
  size_t v = put_billboards(&t, &x, cloud, sides);
  if (cloud->limb_triangles) put_limbs(&t, &x, v, nt);
  if (t.oom) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", wrl_path);
    goto done;
  }
  r = write_files(wrl_path, dir, png, len + 200, &x, nm, &t, err);

done:
  free(t.data);
  free(dir);
  free(stem);
  free(png);
  return r;
}
