#include <dualspectra/dualspectra.h>
#include <stdio.h>
#include <stdlib.h>

/* Every call returns a status; on failure, say why and stop. */
static void check(ds_status status) {
  if (status != DS_OK) {
    fprintf(stderr, "error: %s (%s)\n", ds_last_error_message(), ds_status_name(status));
    exit(1);
  }
}

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s FULL PARTIAL (.off, .obj or .ply)\n", argv[0]);
    return 2;
  }
  /* From files; from your arrays: ds_mesh_create_from_host(xyz, n_vertices, tri, n_faces, &full). */
  ds_mesh *full, *part;
  check(ds_mesh_read(argv[1], &full));
  check(ds_mesh_read(argv[2], &part));
  if (ds_mesh_warning(part)) fprintf(stderr, "warning: %s\n", ds_mesh_warning(part));

  /* Lighter than the defaults, so that this example runs in seconds. */
  ds_options* options;
  check(ds_options_create(&options));
  check(ds_options_set(options, "k", "8"));
  check(ds_options_set(options, "max_iterations", "10"));

  ds_localizer* localizer; /* prepare the full shape once, */
  check(ds_localizer_create(full, options, NULL, NULL, &localizer));
  ds_result* found; /* then locate any number of partials on it */
  check(ds_localizer_locate(localizer, part, NULL, NULL, &found));

  /* The region: one flag per vertex of full. The confidence, in [0, 1]: the estimated
     probability that the partial is part of full and the region overlaps the true one with
     IoU >= 0.5; reject low ones. */
  size_t n = ds_mesh_n_vertices(full), in_region = 0;
  uint8_t* region = malloc(n);
  double confidence;
  if (!region) return 1;
  check(ds_result_region(found, region, n));
  check(ds_result_confidence(found, &confidence));
  for (size_t i = 0; i < n; ++i) in_region += region[i];
  printf("region: %zu of %zu vertices, confidence %.2f\n", in_region, n, confidence);

  free(region);
  ds_result_destroy(found);
  ds_localizer_destroy(localizer);
  ds_options_destroy(options);
  ds_mesh_destroy(part);
  ds_mesh_destroy(full);
  return 0;
}
