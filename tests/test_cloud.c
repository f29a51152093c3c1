/* test_cloud.c — step 3, first version: the cloud of a real tree is a
 * mesh of textured quads lying on their planes, inside the original's
 * bounds (+- epsilon), deterministic, and it survives glTF output. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bbc.h"
#include "test_util.h"

static void build(const bbc_mesh *m, int quality, bbc_planeset *s, bbc_mesh *cloud) {
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.epsilon_pct = 6;
  o.params.clustering = 0;
  o.params.quality = quality;
  o.params.texres = 128;
  bbc_error err;
  if (bbc_planes_find(m, &o, s, &err) != BBC_OK) fail_msg("%s", err.message);
  if (bbc_cloud_build(m, s, &o.params, cloud, &err) != BBC_OK) fail_msg("%s", err.message);
}

static void test_cloud_of_a_tree(void **state) {
  (void)state;
  char path[1024];
  tu_data_path(path, sizeof path, "trees/eztree/aspen_small.obj");
  if (!tu_have_file(path)) skip();
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, NULL, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  for (int quality = 0; quality <= 2; quality += 2) {
    bbc_planeset s;
    bbc_mesh cloud;
    build(&m, quality, &s, &cloud);
    /* One quad per plane (polyskip 0, no cardboard planes). */
    assert_int_equal(cloud.triangle_count, 2 * s.plane_count);
    assert_int_equal(cloud.vertex_count, 4 * s.plane_count);
    /* Every quad corner lies on its plane; the quads' bounds stay near the
     * original's (a minimum-area rectangle's corners can stick out of the
     * faces' own bounds, so this is looser than epsilon; see README). */
    for (size_t q = 0; q < cloud.triangle_count / 2; q++) {
      const float *nn = cloud.normals + 3 * cloud.indices[6 * q];
      const double *p0 = cloud.positions + 3 * cloud.indices[6 * q];
      for (int c = 1; c < 4; c++) {
        const double *pc = cloud.positions + 3 * (cloud.indices[6 * q] + (uint32_t)c);
        double d = 0;
        for (int k = 0; k < 3; k++) d += (pc[k] - p0[k]) * nn[k];
        assert_true(fabs(d) < 1e-5 * m.radius);
      }
    }
    for (int k = 0; k < 3; k++) {
      printf("axis %d: cloud [%g, %g] model [%g, %g] eps %g\n", k, cloud.bbox_min[k],
             cloud.bbox_max[k], m.bbox_min[k], m.bbox_max[k], s.epsilon_abs);
      assert_true(cloud.bbox_min[k] >= m.bbox_min[k] - 0.25 * m.radius);
      assert_true(cloud.bbox_max[k] <= m.bbox_max[k] + 0.25 * m.radius);
    }
    /* The atlas has real transparency: alpha 0 and 255 only at quality 2. */
    const bbc_image *a = &cloud.textures[0].image;
    size_t zero = 0, full = 0, other = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
      uint8_t al = a->rgba[4 * i + 3];
      zero += al == 0;
      full += al == 255;
      other += al != 0 && al != 255;
    }
    assert_true(zero > 0 && full > 0);
    assert_int_equal(other, 0);
    /* Deterministic. */
    bbc_planeset s2;
    bbc_mesh c2;
    build(&m, quality, &s2, &c2);
    assert_int_equal(c2.textures[0].image.width, a->width);
    assert_memory_equal(c2.textures[0].image.rgba, a->rgba, (size_t)a->width * a->height * 4);
    assert_memory_equal(c2.positions, cloud.positions, cloud.vertex_count * 3 * sizeof(double));
    bbc_mesh_free(&c2);
    bbc_planeset_free(&s2);
    /* glTF round trip. */
    char *dir = tu_make_temp_dir();
    char out[1024];
    snprintf(out, sizeof out, "%s/aspen.glb", dir);
    assert_int_equal(bbc_mesh_write_gltf(out, &cloud, NULL, &err), BBC_OK);
    bbc_mesh back;
    if (bbc_mesh_load(out, NULL, &back, &err) != BBC_OK) fail_msg("%s", err.message);
    assert_int_equal(back.triangle_count, cloud.triangle_count);
    assert_true(back.texture_count == 1 && back.textures[0].has_alpha);
    bbc_mesh_free(&back);
    tu_remove_dir(dir);
    free(dir);
    bbc_mesh_free(&cloud);
    bbc_planeset_free(&s);
  }
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_cloud_of_a_tree),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
