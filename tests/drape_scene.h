/* drape_scene.h - the sphere drop of docs/scenes.md as the physics tests and bench/drape.c build it:
   a 1 m cloth of n x n vertices (0.1 kg/m^2) dropped flat from y = 1 + lift onto a sphere of
   radius 0.3 at the origin, friction 0.5, self-collision on, the other settings from def (a
   world def made by cloth_default_world_def). Include after cloth.h. */
#ifndef CLOTH_TESTS_DRAPE_SCENE_H
#define CLOTH_TESTS_DRAPE_SCENE_H

/* 1 when *w (with the cloth as *piece, its mesh in *m for the caller to free) was made. */
static int drape_scene_world(cloth_world_def def, int32_t n, double lift, cloth_world **w, cloth_mesh *m, int32_t *piece)
{
    cloth_piece_def p = cloth_default_piece_def();
    cloth_obstacle_def od = cloth_default_obstacle_def();
    int32_t i;
    def.self_collision = 1;
    p.material.areal_density = (cloth_real)0.1;
    od.shape = CLOTH_OBSTACLE_SPHERE;
    od.radius = (cloth_real)0.3;
    od.friction_static = od.friction_kinetic = (cloth_real)0.5;
    *w = NULL;
    if (cloth_mesh_grid(m, n, n, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return 0;
    for (i = 0; i < m->vertex_count; ++i) m->x[3 * i + 1] = (cloth_real)(1 + lift);
    return cloth_world_create(w, &def) == CLOTH_SUCCESS && cloth_world_add_piece(*w, m, &p, piece) == CLOTH_SUCCESS &&
           cloth_world_add_obstacle(*w, &od, NULL) == CLOTH_SUCCESS;
}

#endif
