/* obj_frames.c - read a cloth from an OBJ file, simulate it, write the frames.

   With a path argument it reads that OBJ (any triangle or polygon mesh; uv, when present, is
   the rest shape). Without one it first writes a round tablecloth (a disc of radius 0.4 m,
   from cloth_mesh_disc) to build/examples/disc.obj and reads that. The cloth is dropped from
   where the file puts it, lifted 0.5 m above the file's lowest point, onto a table (a box)
   and written every 10th frame to build/examples/obj_frame_NNNN.obj, which any 3D viewer
   opens (Blender, MeshLab, ParaView). Run it from the repository root: `make examples` makes
   build/examples/.

   What it teaches: reading meshes (errors come back with their line), writing them, the
   world's view of a piece as a mesh, a box obstacle. PLY, VTK and OFF work the same way
   (CLOTH_FORMAT_AUTO detects them).

       cc -std=c99 -O2 -o build/examples/obj_frames examples/obj_frames.c -lm
       ./build/examples/obj_frames [cloth.obj] [--short]
   It exits with 1 when a step fails or a check does not hold. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    const char *path = "build/examples/disc.obj";
    const char broken[] = "v 0 0 0\nv 1 0 0\nv 0 1 oops\nf 1 2 3\n"; /* line 3 is wrong */
    int quick = 0, builtin, frames, frame, a;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_obstacle_def table = cloth_default_obstacle_def();
    cloth_world *world = NULL;
    cloth_mesh mesh, back;
    cloth_io_error error;
    int32_t piece, i;
    cloth_real lowest = (cloth_real)1e30;
    char name[64];
    cloth_result r;

    for (a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--short") == 0) quick = 1;
        else path = argv[a];
    }
    frames = quick ? 60 : 180;
    builtin = strcmp(path, "build/examples/disc.obj") == 0;

    /* A bad file is refused with a named error and its place: here line 3. */
    r = cloth_mesh_read_memory(&mesh, broken, sizeof broken - 1, CLOTH_FORMAT_OBJ, &error, NULL);
    printf("reading a broken OBJ: %s, line %ld: %s\n", cloth_result_string(r), (long)error.line, error.message);
    if (r == CLOTH_SUCCESS || error.line != 3) { printf("FAILED: the broken OBJ was not refused at line 3\n"); return 1; }

    if (builtin) {
        r = cloth_mesh_disc(&mesh, (cloth_real)0.4, 10, 8, NULL); /* 10 rings, 8 vertices on the first */
        if (r == CLOTH_SUCCESS) r = cloth_mesh_write_file(&mesh, path, CLOTH_FORMAT_OBJ);
        cloth_mesh_free(&mesh);
        if (r != CLOTH_SUCCESS) { printf("FAILED: writing %s (%s; does build/examples/ exist?)\n", path, cloth_result_string(r)); return 1; }
    }
    r = cloth_mesh_read_file(&mesh, path, CLOTH_FORMAT_AUTO, &error, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: %s line %ld: %s\n", path, (long)error.line, error.message); return 1; }
    printf("%s: %d vertices, %d triangles, %s uv\n", path, (int)mesh.vertex_count, (int)mesh.triangle_count,
           mesh.uv ? "with" : "without");

    /* Put it 0.5 m above the table top (y = 0.75). */
    for (i = 0; i < mesh.vertex_count; ++i) if (mesh.x[3 * i + 1] < lowest) lowest = mesh.x[3 * i + 1];
    for (i = 0; i < mesh.vertex_count; ++i) mesh.x[3 * i + 1] += (cloth_real)1.25 - lowest;

    /* The table: a box 1 m x 0.75 m x 0.6 m standing on y = 0, placed by its pose. */
    table.shape = CLOTH_OBSTACLE_BOX;
    table.half_extents[0] = (cloth_real)0.3;
    table.half_extents[1] = (cloth_real)0.375;
    table.half_extents[2] = (cloth_real)0.3;
    table.pose.translation[1] = (cloth_real)0.375;

    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_obstacle(world, &table, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: setup (%s)\n", cloth_result_string(r)); goto done; }

    for (frame = 0; frame < frames; ++frame) {
        r = cloth_world_step(world, (cloth_real)(1.0 / 60), NULL);
        if (r != CLOTH_SUCCESS) { printf("FAILED: step %d (%s)\n", frame, cloth_result_string(r)); goto done; }
        if (frame % 10 == 9) {
            /* cloth_world_mesh is a view of the piece (its triangles and uv, the current
               positions), valid until the world changes: write it as it is. */
            cloth_mesh now = cloth_world_mesh(world, piece);
            snprintf(name, sizeof name, "build/examples/obj_frame_%04d.obj", frame + 1);
            r = cloth_mesh_write_file(&now, name, CLOTH_FORMAT_OBJ);
            if (r != CLOTH_SUCCESS) { printf("FAILED: writing %s (%s)\n", name, cloth_result_string(r)); goto done; }
        }
    }

    /* Check the last file: read back, it is the world's mesh to the last bit (the writer
       prints enough digits to round-trip), and the cloth lies on the table (y = 0.75 plus
       the 1 mm thickness, at the centre), draping over its edges. */
    r = cloth_mesh_read_file(&back, name, CLOTH_FORMAT_OBJ, &error, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: reading %s back (%s)\n", name, cloth_result_string(r)); goto done; }
    {
        cloth_mesh now = cloth_world_mesh(world, piece);
        int same = back.vertex_count == now.vertex_count && back.triangle_count == now.triangle_count &&
                   memcmp(back.x, now.x, sizeof(cloth_real) * 3 * (size_t)now.vertex_count) == 0 &&
                   memcmp(back.tri, now.tri, sizeof(int32_t) * 3 * (size_t)now.triangle_count) == 0;
        cloth_real top = now.x[1], low = now.x[1]; /* the disc's vertex 0 is its centre */
        for (i = 0; i < now.vertex_count; ++i) if (now.x[3 * i + 1] < low) low = now.x[3 * i + 1];
        cloth_mesh_free(&back);
        if (!same) { printf("FAILED: %s does not read back as written\n", name); r = CLOTH_ERROR_INVALID_ARGUMENT; goto done; }
        printf("%d frames: %s reads back exactly; centre at y = %.4f m, lowest point %.3f m\n", frames, name, (double)top, (double)low);
        if (builtin) /* the checks for the built-in disc */
            if (fabs((double)top - 0.751) > 0.002 || !(low < 0.7)) {
                printf("FAILED: the tablecloth does not lie on the table and hang over its edges\n");
                r = CLOTH_ERROR_INVALID_ARGUMENT;
                goto done;
            }
    }
    printf("ok\n");
done:
    cloth_world_destroy(world);
    cloth_mesh_free(&mesh);
    return r == CLOTH_SUCCESS ? 0 : 1;
}
