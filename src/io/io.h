/*
 * io.h — the readers' and writers' shared pieces (src/io): atomic output
 * files, paths, whole-file reading, the PNG encoder, and the readers we own
 * behind bbc_mesh_load. Not installed.
 */
#ifndef BBC_IO_H
#define BBC_IO_H

#include "base.h"

/* A name safe in file names and OBJ statements: [A-Za-z0-9_.-], others
 * '_'; "unnamed" when empty. */
void bbc__safe_name(const char *in, char *out, size_t n);
/* v as "%.*g" with `digits` significant digits, spelt as in the C locale
 * whatever the process's locale (src/io/number.c); out: n bytes, at least
 * BBC__NUMBER_TEXT for any double. */
#define BBC__NUMBER_TEXT 64
void bbc__number_text(char *out, size_t n, int digits, double v);

/* The writers' text (src/io/text_out.c): a growing buffer (zeroed: empty)
 * whose appends never fail loudly: a growth that fails sets `oom`, and
 * every later append is ignored, so a writer checks `oom` once. Numbers go
 * through bbc__text_number (bbc__number_text's spelling); bbc__text_printf
 * is for everything else (its format takes no floating-point conversion). */
typedef struct bbc__text {
  unsigned char *data;
  size_t size, cap;
  int oom;
} bbc__text;
void bbc__text_append(bbc__text *t, const void *data, size_t n);
void bbc__text_puts(bbc__text *t, const char *s);
void bbc__text_printf(bbc__text *t, const char *fmt, ...) BBC__PRINTF(2, 3);
void bbc__text_number(bbc__text *t, int digits, double v);
/* Writes what the buffer holds to f and empties it (a file written as it
 * goes); 0 when the write failed or the buffer ran out of memory. */
int bbc__text_flush(bbc__text *t, FILE *f);
void bbc__text_free(bbc__text *t);

/* The stem of the files an output writes beside it (its textures): the
 * output's whole file name with the extension's dot as '_' ("u.gltf" ->
 * "u_gltf", "u.obj" -> "u_obj"), so that outputs of different formats in
 * one folder never share a side file; `safe`: as bbc__safe_name. */
void bbc__side_file_stem(const char *path, int safe, char *out, size_t n);

/* Checks that `path` names a readable regular file; BBC_ERROR_NOT_FOUND,
 * BBC_ERROR_NOT_A_FILE or BBC_ERROR_IO with a message otherwise. */
bbc_result bbc__check_input_file(const char *path, bbc_error *err);

/* Lower-case extension of `path` without the dot, written to ext (at most
 * ext_size bytes); "" when none. */
void bbc__path_extension(const char *path, char *ext, size_t ext_size);

/* Folder part of `path` including the trailing '/', or "" when none. */
void bbc__path_folder(const char *path, char *folder, size_t folder_size);
/* 1 when `path` is a regular file. */
int bbc__file_exists(const char *path);

/* ---- atomic output files -------------------------------------------------
 * Writes go to a temporary file in the destination folder; commit renames it
 * over the destination, abort removes it. A crash or a failed write never
 * leaves a half-written file under the final name. */
typedef struct bbc__atomic_file {
  FILE *fp;
  char *final_path;
  char *temp_path;
} bbc__atomic_file;

bbc_result bbc__atomic_open(bbc__atomic_file *af, const char *path, bbc_error *err);
/* Flushes, checks for write errors, renames. Closes in every case. */
bbc_result bbc__atomic_commit(bbc__atomic_file *af, bbc_error *err);

void bbc__atomic_abort(bbc__atomic_file *af);

/* ---- texture files (src/io/texture_path.c) --------------------------------
 * How a model spells a texture reference. Each reader's spelling is read as
 * that reader always has, so that every texture found before is found again
 * under the same path. */
typedef enum bbc__texture_spelling {
  /* A file path as exporters write it (PLY's TextureFile comment):
   * backslashes separate folders too (Windows exporters). */
  BBC__TEXTURE_FILE,
  /* As FILE, but below the model's folder without any leading "./", and
   * even when absolute (an exporter's "\textures\bark.png"): the formats
   * Assimp reads (OBJ's map_Kd, 3DS, AC3D, glTF, ...). */
  BBC__TEXTURE_ASSIMP,
  /* A URL's path with its %XX escapes decoded (VRML's ImageTexture url):
   * only '/' separates folders (RFC 3986 3.3). */
  BBC__TEXTURE_URL
} bbc__texture_spelling;

/* Finds the file a model's texture reference `ref` names; the first regular
 * file of: the reference as written when it is absolute; the reference
 * below the model's folder (FILE, URL: when it is relative); its base name
 * in the model's folder; its base name in textures/, Textures/,
 * ../textures/ and ../Textures/ beside the model; then those places again
 * with the base name's case ignored (when one file matches). Blanks after
 * the reference are dropped. Writes the file's path to
 * out (n bytes) and returns 1; when there is none, returns 0 with the
 * reference as written below the model's folder (or absolute) in out, the
 * path a failed read names. */
int bbc__texture_resolve(const char *model_path, const char *ref, bbc__texture_spelling spelling,
                         char *out, size_t n);

/* A PNG file of the image in memory (image_io.c): *out from malloc. */
bbc_result bbc__png_encode(const bbc_image *image, uint8_t **out, size_t *out_size);

/* ---- loaders (src/io) ---------------------------------------------------- */
/* Before any reader (src/io/sniff.c): compressed files, LAS, images,
 * material libraries and forest files refused with what they are; an OBJ or
 * XYZ whose last line is cut short, a glTF whose accessors or buffers claim
 * more bytes than it holds, refused (BBC_ERROR_CORRUPT); an OBJ whose last
 * vertices no face uses, said. `data`/`size` when from_memory. */
bbc_result bbc__sniff_input(const char *name, const void *data, size_t size, int from_memory,
                            const bbc_load_options *options, bbc_error *err);
/* A model Assimp reads, from its file (src/io/load_assimp.c). */
bbc_result bbc__load_assimp(const char *path, const bbc_load_options *options, bbc_mesh *mesh,
                            bbc_error *err);
/* Reads a whole file into a NUL-terminated buffer (*size bytes without
 * the NUL); free with free() (src/io/text_scan.c). */
bbc_result bbc__read_whole_file(const char *path, char **data, size_t *size, bbc_error *err);

/* Run-length encoded BMP (BI_RLE8, BI_RLE4), which stb_image does not
 * read (src/io/bmp_rle.c): whether the bytes are one, and decoding. */
int bbc__is_bmp_rle(const uint8_t *data, size_t size);
bbc_result bbc__bmp_rle_decode(const uint8_t *data, size_t size, const char *name, bbc_image *image,
                               bbc_error *err);
/* The readers we own (src/io/load_vrml.c, load_ply.c, load_xyz.c), on a
 * file's bytes in memory: `buf` holds `size` bytes and a NUL after them and
 * is taken over (freed) by the call; `path` names the input in messages
 * (and, for PLY, where its textures are). PLY and XYZ finish the mesh
 * themselves; the caller finalizes a VRML mesh (bbc_mesh_load does). */
bbc_result bbc__parse_vrml(const char *path, char *buf, size_t size,
                           const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);
/* PLY (load_ply.c, ply_header.c, ply_mesh.c), every .ply file: a triangle
 * mesh when the header declares `face` or `tristrips` records (polygons
 * triangulated as fans, one material "default", one group named after the
 * file's stem), a point cloud otherwise. Finishes the mesh with
 * bbc_mesh_finalize and frees it on failure; `options` may be NULL
 * (defaults). */
bbc_result bbc__parse_ply(const char *path, char *buf, size_t size, const bbc_load_options *options,
                          bbc_mesh *mesh, bbc_error *err);
bbc_result bbc__parse_xyz(const char *path, char *buf, size_t size, const bbc_load_options *options,
                          bbc_mesh *mesh, bbc_error *err);
/* A model Assimp reads, from memory (`name`'s extension is its format hint;
 * no other files: an OBJ's MTL, a glTF's buffers are not found). */
bbc_result bbc__load_assimp_memory(const char *name, const void *data, size_t size,
                                   const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);

/* An OBJ file's bytes (`buf`, `size` and a NUL) as Assimp's OBJ importer
 * would read them (src/io/load_obj.c): the mesh as bbc__load_assimp gives
 * it, not finalized; or, for what it leaves to Assimp, *deferred = 1 and
 * BBC_OK with the mesh untouched. */
bbc_result bbc__parse_obj(const char *path, const char *buf, size_t size,
                          const bbc_load_options *options, bbc_mesh *mesh, int *deferred,
                          bbc_error *err);

/* What every load ends with (src/io/load.c): the mesh finalized (when
 * `finalize`: the readers other than PLY and XYZ), freed when `r` or the
 * finishing fails, else moved near 0. Returns the result. */
bbc_result bbc__load_finish(const char *name, bbc_result r, int finalize,
                            const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);
/* Our code after Assimp on a scene the caller built (the fuzzer of our mesh
 * building, fuzz/fuzz_scene.c): materials, textures (embedded ones decoded
 * from memory), nodes, meshes, then bbc__load_finish; the scene stays the
 * caller's; `options` may not be NULL. */
struct aiScene;
/* The conversion alone (no finishing): what bbc__load_assimp does with the
 * scene Assimp read, for a scene built by our own reader (load_obj.c). */
bbc_result bbc__assimp_convert(const char *path, const struct aiScene *scene,
                               const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);
/* A material built by hand as Assimp lays one out (each property and its
 * data malloc'd, as load_obj.c and fuzz_scene.c build them), freed. */
struct aiMaterial;
void bbc__scene_material_free(struct aiMaterial *m);
bbc_result bbc__load_assimp_scene(const char *name, const struct aiScene *scene,
                                  const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);

#endif /* BBC_IO_H */
