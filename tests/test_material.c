/* Tests of the material module: validation, membrane conversions, the readings of seed 002
   and of ARCSim's files, presets, Kawabata and cantilever conversions, stable time steps.
   Expected values are derived here from unit definitions, closed forms or an independent
   computation (energies written in the source's own form, a power iteration on an assembled
   stiffness matrix, a simulation), never copied from the implementation. */
#include "runner.h"
#include "../cloth.h"
#include <stdlib.h>
#include <string.h>

/* Relative tolerance of one conversion in the build's precision. */
#define REL (sizeof(cloth_real) == sizeof(float) ? 4e-6 : 1e-12)

static double rel_err(double a, double b)
{
    double s = fabs(a) > fabs(b) ? fabs(a) : fabs(b);
    return s > 0 ? fabs(a - b) / s : 0;
}

/* The membrane energy per rest area of the model the material feeds (cloth.h's form). */
static double model_energy(const cloth_material *m, double e11, double e22, double e12)
{
    return 0.5 * ((double)m->stretch_warp * e11 * e11 + 2.0 * (double)m->stretch_coupling * e11 * e22 +
                  (double)m->stretch_weft * e22 * e22) + 2.0 * (double)m->shear * e12 * e12;
}

static int same_material(const cloth_material *a, const cloth_material *b)
{
    return a->areal_density == b->areal_density && a->stretch_warp == b->stretch_warp &&
           a->stretch_weft == b->stretch_weft && a->stretch_coupling == b->stretch_coupling && a->shear == b->shear &&
           a->bend_warp == b->bend_warp && a->bend_weft == b->bend_weft &&
           a->damping_stiffness == b->damping_stiffness && a->damping_relative == b->damping_relative;
}

/* ---- the default and validation ----------------------------------------------------- */

TEST(default_is_a_valid_midweight_cotton)
{
    cloth_material m = cloth_default_material(), p;
    cloth_real c;
    ENSURE(cloth_material_validate(&m) == CLOTH_SUCCESS);
    ENSURE(cloth_material_preset("cotton", &p) == CLOTH_SUCCESS);
    ENSURE(same_material(&m, &p));
    /* mid-weight shirting is 100-200 g/m^2 */
    ENSURE(m.areal_density >= 0.1 && m.areal_density <= 0.2);
    /* woven cotton: much stiffer in tension than in shear, warp at least as stiff as weft */
    ENSURE(m.stretch_warp >= m.stretch_weft && m.shear < 0.05 * m.stretch_weft);
    /* shirting-class cantilever bending lengths are about 1.5 to 2.5 cm */
    ENSURE(cloth_bending_length(m.bend_warp, m.areal_density, (cloth_real)9.81, &c) == CLOTH_SUCCESS);
    ENSURE(c > 0.015 && c < 0.025);
    ENSURE(m.damping_stiffness == 0 && m.damping_relative == 0);
}

TEST(validate_rejects_non_physical_values)
{
    cloth_material base = cloth_default_material(), m;
    cloth_real *fields[9];
    double lim = sqrt((double)base.stretch_warp * (double)base.stretch_weft);
    int i;
#define CHECK_FIELD(field, value, expected) do { m = base; m.field = (cloth_real)(value); \
        ENSURE(cloth_material_validate(&m) == (expected)); } while (0)
    CHECK_FIELD(areal_density, 0, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(areal_density, -0.1, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(stretch_warp, -1, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(stretch_weft, 0, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(shear, 0, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(shear, -5, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(bend_warp, -1e-9, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(bend_weft, 0, CLOTH_SUCCESS);
    CHECK_FIELD(damping_stiffness, -1e-6, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(damping_relative, -1e-6, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(damping_relative, 0.5, CLOTH_SUCCESS);
    /* positive definiteness of the membrane: C11 C22 - C12^2 > 0, either sign of C12 */
    CHECK_FIELD(stretch_coupling, 0.999 * lim, CLOTH_SUCCESS);
    CHECK_FIELD(stretch_coupling, -0.999 * lim, CLOTH_SUCCESS);
    CHECK_FIELD(stretch_coupling, 1.001 * lim, CLOTH_ERROR_INVALID_ARGUMENT);
    CHECK_FIELD(stretch_coupling, -1.001 * lim, CLOTH_ERROR_INVALID_ARGUMENT);
#undef CHECK_FIELD
    /* NaN or infinity anywhere is reported as not finite, before any range problem */
    m = base;
    fields[0] = &m.areal_density; fields[1] = &m.stretch_warp; fields[2] = &m.stretch_weft;
    fields[3] = &m.stretch_coupling; fields[4] = &m.shear; fields[5] = &m.bend_warp; fields[6] = &m.bend_weft;
    fields[7] = &m.damping_stiffness; fields[8] = &m.damping_relative;
    for (i = 0; i < 9; ++i) {
        cloth_real keep = *fields[i];
        *fields[i] = (cloth_real)NAN;
        ENSURE(cloth_material_validate(&m) == CLOTH_ERROR_NOT_FINITE);
        *fields[i] = (cloth_real)-INFINITY;
        ENSURE(cloth_material_validate(&m) == CLOTH_ERROR_NOT_FINITE);
        *fields[i] = keep;
    }
    ENSURE(cloth_material_validate(&m) == CLOTH_SUCCESS);
    m.areal_density = -1;
    m.shear = (cloth_real)NAN;
    ENSURE(cloth_material_validate(&m) == CLOTH_ERROR_NOT_FINITE);
}

/* ---- membrane conversions ---------------------------------------------------------- */

TEST(isotropic_membrane_relations)
{
    cloth_material m = cloth_default_material(), before;
    cloth_membrane_engineering e;
    double y = 1234.5, nu = 0.3;
    ENSURE(cloth_material_set_isotropic(&m, (cloth_real)y, (cloth_real)nu) == CLOTH_SUCCESS);
    /* C11 = Y/(1 - nu^2) */
    ENSURE(rel_err(m.stretch_warp, y / (1 - nu * nu)) < REL);
    ENSURE(m.stretch_warp == m.stretch_weft);
    /* isotropy: C11 - C12 = Y/(1 + nu) = 2 C33 and C12 / C11 = nu */
    ENSURE(rel_err((double)m.stretch_warp - (double)m.stretch_coupling, 2.0 * (double)m.shear) < 10 * REL);
    ENSURE(rel_err((double)m.stretch_coupling / (double)m.stretch_warp, nu) < 10 * REL);
    ENSURE(cloth_material_engineering(&m, &e) == CLOTH_SUCCESS);
    ENSURE(rel_err(e.tensile_warp, y) < 10 * REL && rel_err(e.tensile_weft, y) < 10 * REL);
    ENSURE(rel_err(e.poisson_warp_weft, nu) < 10 * REL);
    /* an auxetic sheet is allowed; |nu| >= 1 is not, and the material is then unchanged */
    ENSURE(cloth_material_set_isotropic(&m, (cloth_real)y, (cloth_real)-0.5) == CLOTH_SUCCESS);
    ENSURE(m.stretch_coupling < 0 && cloth_material_validate(&m) == CLOTH_SUCCESS);
    before = m;
    ENSURE(cloth_material_set_isotropic(&m, (cloth_real)y, 1) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_set_isotropic(&m, (cloth_real)y, -1) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_set_isotropic(&m, (cloth_real)y, (cloth_real)1.5) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_set_isotropic(&m, 0, (cloth_real)0.3) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_set_isotropic(&m, (cloth_real)y, (cloth_real)NAN) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(same_material(&m, &before));
}

TEST(orthotropic_engineering_round_trip_and_uniaxial_test)
{
    cloth_rng rng = cloth_rng_make(7);
    int trial;
    for (trial = 0; trial < 50; ++trial) {
        cloth_material m = cloth_default_material();
        cloth_membrane_engineering e, back;
        double c11, c12, c22, det, n, e11, e22;
        e.tensile_warp = (cloth_real)(50 + 9950 * cloth_rng_uniform(&rng));
        e.tensile_weft = (cloth_real)(50 + 9950 * cloth_rng_uniform(&rng));
        /* keep nu12 nu21 < 1: |nu12| < sqrt(Y1/Y2) */
        e.poisson_warp_weft = (cloth_real)((2 * cloth_rng_uniform(&rng) - 1) * 0.95 *
                                           sqrt((double)e.tensile_warp / (double)e.tensile_weft));
        e.shear = (cloth_real)(1 + 200 * cloth_rng_uniform(&rng));
        ENSURE(cloth_material_set_engineering(&m, &e) == CLOTH_SUCCESS);
        ENSURE(cloth_material_validate(&m) == CLOTH_SUCCESS);
        ENSURE(cloth_material_engineering(&m, &back) == CLOTH_SUCCESS);
        ENSURE(rel_err(back.tensile_warp, e.tensile_warp) < 100 * REL);
        ENSURE(rel_err(back.tensile_weft, e.tensile_weft) < 100 * REL);
        ENSURE(fabs((double)back.poisson_warp_weft - (double)e.poisson_warp_weft) < 100 * REL);
        ENSURE(back.shear == e.shear);
        /* a uniaxial warp test: N = (n, 0). Solving D (E11, E22) = (n, 0) must give
           E11 = n / Y1 and E22 = -nu12 E11 (the definitions of Y1 and nu12) */
        c11 = m.stretch_warp; c12 = m.stretch_coupling; c22 = m.stretch_weft;
        det = c11 * c22 - c12 * c12;
        n = 3.0;
        e11 = c22 * n / det;
        e22 = -c12 * n / det;
        ENSURE(rel_err(e11, n / (double)e.tensile_warp) < 100 * REL);
        ENSURE(fabs(e22 + (double)e.poisson_warp_weft * e11) < 100 * REL * fabs(e11));
        /* reciprocity: nu21 = nu12 Y2 / Y1 is the weft test's ratio C12 / C11 */
        ENSURE(fabs((double)e.poisson_warp_weft * (double)e.tensile_weft / (double)e.tensile_warp - c12 / c11) <
               100 * REL);
    }
    {
        cloth_material m = cloth_default_material(), before = m;
        cloth_membrane_engineering e;
        e.tensile_warp = 1000; e.tensile_weft = 4000; e.shear = 10;
        e.poisson_warp_weft = (cloth_real)0.5; /* nu21 = 2: nu12 nu21 = 1 */
        ENSURE(cloth_material_set_engineering(&m, &e) == CLOTH_ERROR_INVALID_ARGUMENT);
        e.poisson_warp_weft = (cloth_real)0.49;
        e.shear = 0;
        ENSURE(cloth_material_set_engineering(&m, &e) == CLOTH_ERROR_INVALID_ARGUMENT);
        ENSURE(same_material(&m, &before));
        e.shear = 10;
        ENSURE(cloth_material_set_engineering(&m, &e) == CLOTH_SUCCESS);
        m.stretch_coupling = m.stretch_warp * 10;
        ENSURE(cloth_material_engineering(&m, &e) == CLOTH_ERROR_INVALID_ARGUMENT);
    }
}

TEST(lame_membrane_is_isotropic_stvk)
{
    cloth_rng rng = cloth_rng_make(3);
    cloth_material m = cloth_default_material();
    cloth_membrane_engineering e;
    double lambda = 20.5, mu = 33.25;
    int i;
    ENSURE(cloth_material_set_lame(&m, (cloth_real)lambda, (cloth_real)mu) == CLOTH_SUCCESS);
    for (i = 0; i < 20; ++i) {
        double e11 = 0.2 * cloth_rng_uniform(&rng) - 0.1, e22 = 0.2 * cloth_rng_uniform(&rng) - 0.1;
        double e12 = 0.2 * cloth_rng_uniform(&rng) - 0.1;
        /* W = lambda/2 (tr E)^2 + mu tr(E^2) with E symmetric */
        double w = 0.5 * lambda * (e11 + e22) * (e11 + e22) + mu * (e11 * e11 + e22 * e22 + 2 * e12 * e12);
        ENSURE(rel_err(model_energy(&m, e11, e22, e12), w) < 10 * REL);
    }
    ENSURE(cloth_material_engineering(&m, &e) == CLOTH_SUCCESS);
    ENSURE(rel_err(e.tensile_warp, 4 * mu * (lambda + mu) / (lambda + 2 * mu)) < 10 * REL);
    ENSURE(rel_err(e.poisson_warp_weft, lambda / (lambda + 2 * mu)) < 10 * REL);
    /* lambda may be negative down to -mu (2D bulk modulus lambda + mu > 0) */
    ENSURE(cloth_material_set_lame(&m, (cloth_real)(-0.5 * mu), (cloth_real)mu) == CLOTH_SUCCESS);
    ENSURE(cloth_material_set_lame(&m, (cloth_real)-mu, (cloth_real)mu) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_set_lame(&m, (cloth_real)lambda, 0) == CLOTH_ERROR_INVALID_ARGUMENT);
}

/* ---- seed 002 and ARCSim readings ---------------------------------------------------- */

TEST(seed002_fit_reading)
{
    /* seed 002, Table 2: lambda0, lambda1, lambda2 of silk, fleece, denim, linen */
    static const char *names[4] = { "silk", "fleece", "denim", "linen" };
    static const double table[4][3] = { { 1.0e-5, 50, 50 }, { 6.9376e-6, 19.3822, 69.654 },
                                        { 7.7720e-6, 20.2884, 32.6492 }, { 8.4776e-6, 20.1119, 50.830 } };
    cloth_membrane_engineering eng[4];
    int f, i;
    cloth_rng rng = cloth_rng_make(11);
    for (f = 0; f < 4; ++f) {
        cloth_material p, m;
        ENSURE(cloth_material_preset(names[f], &p) == CLOTH_SUCCESS);
        ENSURE(cloth_material_from_fem_fit((cloth_real)table[f][0], (cloth_real)table[f][1], (cloth_real)table[f][2],
                                           p.areal_density, &m) == CLOTH_SUCCESS);
        ENSURE(same_material(&m, &p));
        ENSURE(rel_err(m.bend_warp, table[f][0]) < REL && m.bend_weft == m.bend_warp);
        /* lambda1, lambda2 as Lame's lambda and mu: the isotropic StVK energy */
        for (i = 0; i < 10; ++i) {
            double e11 = 0.1 * cloth_rng_uniform(&rng), e22 = 0.1 * cloth_rng_uniform(&rng);
            double e12 = 0.1 * cloth_rng_uniform(&rng) - 0.05;
            double w = 0.5 * table[f][1] * (e11 + e22) * (e11 + e22) +
                       table[f][2] * (e11 * e11 + e22 * e22 + 2 * e12 * e12);
            ENSURE(rel_err(model_energy(&m, e11, e22, e12), w) < 10 * REL);
        }
        ENSURE(cloth_material_engineering(&m, &eng[f]) == CLOTH_SUCCESS);
        /* plausible 2D Poisson ratios */
        ENSURE(eng[f].poisson_warp_weft > 0.1 && eng[f].poisson_warp_weft < 0.5);
    }
    /* the paper: "silk is more stretchy than fleece" */
    ENSURE(eng[0].tensile_warp < eng[1].tensile_warp);
    {
        cloth_material m = cloth_default_material(), before = m;
        ENSURE(cloth_material_from_fem_fit((cloth_real)1e-5, 50, 0, (cloth_real)0.1, &m) == CLOTH_ERROR_INVALID_ARGUMENT);
        ENSURE(cloth_material_from_fem_fit((cloth_real)1e-5, 50, 50, 0, &m) == CLOTH_ERROR_INVALID_ARGUMENT);
        ENSURE(cloth_material_from_fem_fit((cloth_real)NAN, 50, 50, (cloth_real)0.1, &m) == CLOTH_ERROR_NOT_FINITE);
        ENSURE(same_material(&m, &before));
    }
}

TEST(arcsim_reading_reproduces_arcsim_energies)
{
    /* 11oz-black-denim.json: stretching row 0 and the first bending samples of rows 0 and 2 */
    cloth_real k[4];
    double ke_u = 64.196457e-6, ke_v = 96.951576e-6;
    cloth_material m, p;
    cloth_rng rng = cloth_rng_make(5);
    int i;
    k[0] = (cloth_real)205.352005; k[1] = (cloth_real)10.234077; k[2] = (cloth_real)1013.88629; k[3] = (cloth_real)53.387184;
    ENSURE(cloth_material_from_arcsim((cloth_real)0.324, k, (cloth_real)ke_u, (cloth_real)ke_v, &m) == CLOTH_SUCCESS);
    ENSURE(cloth_material_preset("denim_11oz", &p) == CLOTH_SUCCESS && same_material(&m, &p));
    for (i = 0; i < 20; ++i) {
        /* ARCSim (physics.cpp) doubles the samples and takes the force of
           e = 1/2 K0 E00^2 + K1 E00 E11 + 1/2 K2 E11^2 + K3 E01^2, K = 2 k */
        double e00 = 0.1 * cloth_rng_uniform(&rng), e11 = 0.1 * cloth_rng_uniform(&rng);
        double e01 = 0.1 * cloth_rng_uniform(&rng) - 0.05;
        double kk0 = 2 * (double)k[0], kk1 = 2 * (double)k[1], kk2 = 2 * (double)k[2], kk3 = 2 * (double)k[3];
        double e = 0.5 * kk0 * e00 * e00 + kk1 * e00 * e11 + 0.5 * kk2 * e11 * e11 + kk3 * e01 * e01;
        ENSURE(rel_err(model_energy(&m, e00, e11, e01), e) < 10 * REL);
    }
    for (i = 0; i < 10; ++i) {
        /* ARCSim's hinge energy ke l^2/(2 a) theta^2 / 4 against cloth.h's B l^2/(2 a) theta^2;
           a hinge edge along u bends the weft */
        double l = 0.01 + 0.01 * cloth_rng_uniform(&rng), a = 1e-4 * (1 + cloth_rng_uniform(&rng));
        double theta = cloth_rng_uniform(&rng) - 0.5;
        double shape = l * l / (2 * a);
        ENSURE(rel_err(ke_u * shape * theta * theta / 4, (double)m.bend_weft * shape * theta * theta) < 10 * REL);
        ENSURE(rel_err(ke_v * shape * theta * theta / 4, (double)m.bend_warp * shape * theta * theta) < 10 * REL);
    }
    /* navy-sparkle-sweat's zero-strain row is indefinite as written; ARCSim's clamp of the
       negative coupling to 0 makes it a valid material */
    k[0] = (cloth_real)12.486332; k[1] = (cloth_real)-19.875324; k[2] = (cloth_real)3.272434; k[3] = (cloth_real)17.616289;
    ENSURE((2.0 * k[0]) * (2.0 * k[2]) - (2.0 * k[1]) * (2.0 * k[1]) < 0);
    ENSURE(cloth_material_from_arcsim((cloth_real)0.224, k, (cloth_real)59.469658e-6, (cloth_real)45.625023e-6, &m) ==
           CLOTH_SUCCESS);
    ENSURE(m.stretch_coupling == 0 && cloth_material_validate(&m) == CLOTH_SUCCESS);
    ENSURE(cloth_material_preset("sweater", &p) == CLOTH_SUCCESS && same_material(&m, &p));
    k[3] = (cloth_real)NAN;
    ENSURE(cloth_material_from_arcsim((cloth_real)0.224, k, 0, 0, &m) == CLOTH_ERROR_NOT_FINITE);
}

TEST(measured_presets_agree_with_the_notes)
{
    /* docs/algorithms.md section 2 lists the measured fabrics from heaviest to lightest */
    static const char *order[10] = { "denim_11oz", "ponte_roma", "rib_knit", "blanket", "sweater",
                                     "pants", "swimsuit", "interlock", "tablecloth", "jet_set" };
    /* and ARCSim's bending coefficient ranges (ke = 4 B) of three of them, in SI */
    static const char *ranged[3] = { "denim_11oz", "interlock", "pants" };
    static const double range[3][2] = { { 2.0e-5, 1.2e-4 }, { 7e-6, 3.9e-5 }, { 1.1e-4, 2.3e-4 } };
    cloth_material prev = cloth_default_material(), m;
    int i;
    for (i = 0; i < 10; ++i) {
        ENSURE(cloth_material_preset(order[i], &m) == CLOTH_SUCCESS);
        ENSURE(cloth_material_validate(&m) == CLOTH_SUCCESS);
        if (i > 0) ENSURE(m.areal_density < prev.areal_density);
        prev = m;
    }
    for (i = 0; i < 3; ++i) {
        ENSURE(cloth_material_preset(ranged[i], &m) == CLOTH_SUCCESS);
        ENSURE(4 * (double)m.bend_warp >= range[i][0] * (1 - REL) && 4 * (double)m.bend_warp <= range[i][1]);
        ENSURE(4 * (double)m.bend_weft >= range[i][0] * (1 - REL) && 4 * (double)m.bend_weft <= range[i][1]);
    }
}

TEST(presets_enumerate_and_look_up_by_name)
{
    int32_t n = cloth_material_preset_count(), i, j;
    cloth_material m, by_name, before;
    char upper[64];
    ENSURE(n >= 15);
    ENSURE(cloth_material_preset_name(-1) == NULL && cloth_material_preset_name(n) == NULL);
    ENSURE(cloth_material_preset_source(n) == NULL);
    ENSURE(cloth_material_preset_at(n, &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_preset_at(-1, &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    for (i = 0; i < n; ++i) {
        const char *name = cloth_material_preset_name(i), *c;
        const char *source = cloth_material_preset_source(i);
        ENSURE(name && source && strlen(source) > 20 && strlen(name) < sizeof upper);
        for (j = 0; j < i; ++j) ENSURE(strcmp(name, cloth_material_preset_name(j)) != 0);
        ENSURE(cloth_material_preset_at(i, &m) == CLOTH_SUCCESS);
        ENSURE(cloth_material_validate(&m) == CLOTH_SUCCESS);
        for (c = name, j = 0; *c; ++c, ++j) {
            ENSURE(!(*c >= 'A' && *c <= 'Z'));
            upper[j] = (char)(*c >= 'a' && *c <= 'z' ? *c - 'a' + 'A' : *c);
        }
        upper[j] = 0;
        ENSURE(cloth_material_preset(upper, &by_name) == CLOTH_SUCCESS);
        ENSURE(same_material(&m, &by_name));
    }
    ENSURE(cloth_material_preset("DeNiM_11Oz", &m) == CLOTH_SUCCESS);
    before = m;
    ENSURE(cloth_material_preset("velvet", &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_preset("den", &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_preset("denim ", &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_preset("", &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_preset(NULL, &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(same_material(&m, &before));
}

/* ---- Kawabata --------------------------------------------------------------------------- */

TEST(kes_units_from_their_definitions)
{
    const double gf = 1e-3 * 9.80665, cm = 1e-2, deg = 3.14159265358979323846 / 180;
    cloth_rng rng = cloth_rng_make(17);
    int i;
    /* B: moment per width per curvature, gf cm / cm / (1/cm) = gf cm^2 / cm */
    ENSURE(rel_err(cloth_kes_bending_to_si(1), gf * cm * cm / cm) < REL);
    ENSURE(fabs((double)cloth_kes_bending_to_si(1) - 9.81e-5) < 0.001 * 9.81e-5); /* the notes' rounded value */
    /* G: a shear force of 2 gf per cm of width at 3 degrees; C33 = N12 / gamma with gamma in radians */
    ENSURE(rel_err(cloth_kes_shear_to_si((cloth_real)(2.0 / 3.0)), (2 * gf / cm) / (3 * deg)) < REL);
    /* W: 15 mg/cm^2 */
    ENSURE(rel_err(cloth_kes_mass_to_si(15), 15e-6 / (cm * cm)) < REL);
    /* loads and tensile energy: gf/cm, and gf cm/cm^2 */
    ENSURE(rel_err(cloth_kes_load_to_si(500), 500 * gf / cm) < REL);
    ENSURE(rel_err(cloth_kes_tensile_energy_to_si(8), 8 * gf * cm / (cm * cm)) < REL);
    for (i = 0; i < 20; ++i) {
        cloth_real x = (cloth_real)(1e-3 + 10 * cloth_rng_uniform(&rng));
        ENSURE(rel_err(cloth_kes_bending_from_si(cloth_kes_bending_to_si(x)), x) < 4 * REL);
        ENSURE(rel_err(cloth_kes_shear_from_si(cloth_kes_shear_to_si(x)), x) < 4 * REL);
        ENSURE(rel_err(cloth_kes_mass_from_si(cloth_kes_mass_to_si(x)), x) < 4 * REL);
        ENSURE(rel_err(cloth_kes_bending_to_si(2 * x), 2 * (double)cloth_kes_bending_to_si(x)) < 4 * REL);
    }
}

TEST(kes_tensile_worked_example)
{
    /* By hand: EMT = 5 %, LT = 0.65, Fm = 500 gf/cm. em = 0.05;
       WT = LT Fm em / 2 = 0.65 * 500 * 0.05 / 2 = 8.125 gf cm/cm^2;
       k = 2 WT / em^2 = 16.25 / 0.0025 = 6500 gf/cm = 6500 * 0.980665 N/m = 6374.3225 N/m.
       The linear spring of that stiffness stores 1/2 k em^2 = 7.96790 J/m^2 at EMT, which is
       WT in SI (8.125 * 0.980665). With LT = 1 the stiffness is the secant 500/0.05 gf/cm. */
    cloth_real k1, k2, k3;
    ENSURE(cloth_kes_tensile_stiffness(5, (cloth_real)0.65, 500, &k1) == CLOTH_SUCCESS);
    ENSURE(rel_err(k1, 6374.3225) < REL);
    ENSURE(cloth_kes_tensile_stiffness_from_energy((cloth_real)8.125, 5, &k2) == CLOTH_SUCCESS);
    ENSURE(rel_err(k2, 6374.3225) < REL);
    ENSURE(rel_err(0.5 * (double)k1 * 0.05 * 0.05, cloth_kes_tensile_energy_to_si((cloth_real)8.125)) < 4 * REL);
    ENSURE(cloth_kes_tensile_stiffness(5, 1, 500, &k3) == CLOTH_SUCCESS);
    ENSURE(rel_err(k3, 10000 * 0.980665) < REL);
    ENSURE(cloth_kes_tensile_stiffness(0, 1, 500, &k3) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_kes_tensile_stiffness(5, -1, 500, &k3) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_kes_tensile_stiffness(5, 1, (cloth_real)NAN, &k3) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(cloth_kes_tensile_stiffness_from_energy(0, 5, &k3) == CLOTH_ERROR_INVALID_ARGUMENT);
}

TEST(kes_measurement_to_material)
{
    cloth_kes_measurement kes;
    cloth_material m, before;
    cloth_membrane_engineering e;
    cloth_real k;
    kes.mass = 22; kes.extension_warp = (cloth_real)3.5; kes.extension_weft = 9;
    kes.linearity_warp = (cloth_real)0.7; kes.linearity_weft = (cloth_real)0.55; kes.max_load = 500;
    kes.shear_rigidity = (cloth_real)0.8; kes.bending_warp = (cloth_real)0.2; kes.bending_weft = (cloth_real)0.12;
    ENSURE(cloth_material_from_kes(&kes, (cloth_real)0.25, &m) == CLOTH_SUCCESS);
    ENSURE(m.areal_density == cloth_kes_mass_to_si(kes.mass));
    ENSURE(m.bend_warp == cloth_kes_bending_to_si(kes.bending_warp));
    ENSURE(m.bend_weft == cloth_kes_bending_to_si(kes.bending_weft));
    ENSURE(m.shear == cloth_kes_shear_to_si(kes.shear_rigidity));
    ENSURE(cloth_material_engineering(&m, &e) == CLOTH_SUCCESS);
    ENSURE(cloth_kes_tensile_stiffness(kes.extension_warp, kes.linearity_warp, kes.max_load, &k) == CLOTH_SUCCESS);
    ENSURE(rel_err(e.tensile_warp, k) < 100 * REL);
    ENSURE(cloth_kes_tensile_stiffness(kes.extension_weft, kes.linearity_weft, kes.max_load, &k) == CLOTH_SUCCESS);
    ENSURE(rel_err(e.tensile_weft, k) < 100 * REL);
    ENSURE(fabs((double)e.poisson_warp_weft - 0.25) < 100 * REL);
    before = m;
    kes.extension_weft = 0;
    ENSURE(cloth_material_from_kes(&kes, (cloth_real)0.25, &m) == CLOTH_ERROR_INVALID_ARGUMENT);
    kes.extension_weft = 9;
    kes.bending_weft = (cloth_real)NAN;
    ENSURE(cloth_material_from_kes(&kes, (cloth_real)0.25, &m) == CLOTH_ERROR_NOT_FINITE);
    kes.bending_weft = (cloth_real)0.12;
    ENSURE(cloth_material_from_kes(&kes, 3, &m) == CLOTH_ERROR_INVALID_ARGUMENT); /* nu12 nu21 > 1 */
    ENSURE(same_material(&m, &before));
}

/* ---- Peirce's cantilever ------------------------------------------------------------- */

TEST(cantilever_worked_example)
{
    /* By hand: a strip of 0.2 kg/m^2 (W = 20 mg/cm^2) under g = 9.81 m/s^2 overhangs l = 4 cm
       when its tip touches the 41.5 degree plane. c = l/2 = 2 cm; w = 0.2 * 9.81 = 1.962 N/m^2;
       G = w c^3 = 1.962 * 8e-6 = 1.5696e-5 N m. In ASTM D1388 units G = W c^3 = 20 * 8 =
       160 mg cm = 160e-6 kg * 1e-2 m * 9.81 m/s^2 = 1.5696e-5 N m, the same. */
    cloth_real b, l, c;
    cloth_rng rng = cloth_rng_make(23);
    int i;
    ENSURE(cloth_cantilever_rigidity((cloth_real)0.04, (cloth_real)0.2, (cloth_real)9.81, &b) == CLOTH_SUCCESS);
    ENSURE(rel_err(b, 1.5696e-5) < REL);
    ENSURE(rel_err(b, 160e-6 * 1e-2 * 9.81) < REL);
    ENSURE(cloth_cantilever_overhang((cloth_real)1.5696e-5, (cloth_real)0.2, (cloth_real)9.81, &l) == CLOTH_SUCCESS);
    ENSURE(rel_err(l, 0.04) < 4 * REL);
    ENSURE(cloth_bending_length((cloth_real)1.5696e-5, (cloth_real)0.2, (cloth_real)9.81, &c) == CLOTH_SUCCESS);
    ENSURE(rel_err(c, 0.02) < 4 * REL);
    /* dimensional scaling: l ~ (B / (rho g))^(1/3) */
    ENSURE(cloth_cantilever_overhang((cloth_real)(8 * 1.5696e-5), (cloth_real)0.2, (cloth_real)9.81, &l) == CLOTH_SUCCESS);
    ENSURE(rel_err(l, 0.08) < 4 * REL);
    ENSURE(cloth_cantilever_overhang((cloth_real)1.5696e-5, (cloth_real)1.6, (cloth_real)9.81, &l) == CLOTH_SUCCESS);
    ENSURE(rel_err(l, 0.02) < 4 * REL);
    for (i = 0; i < 20; ++i) {
        cloth_real l0 = (cloth_real)(0.01 + 0.2 * cloth_rng_uniform(&rng)), rho = (cloth_real)(0.05 + cloth_rng_uniform(&rng));
        ENSURE(cloth_cantilever_rigidity(l0, rho, (cloth_real)CLOTH_STANDARD_GRAVITY, &b) == CLOTH_SUCCESS);
        ENSURE(cloth_cantilever_overhang(b, rho, (cloth_real)CLOTH_STANDARD_GRAVITY, &l) == CLOTH_SUCCESS);
        ENSURE(rel_err(l, l0) < 10 * REL);
    }
    ENSURE(cloth_bending_length(0, (cloth_real)0.2, (cloth_real)9.81, &c) == CLOTH_SUCCESS && c == 0);
    ENSURE(cloth_cantilever_rigidity(0, (cloth_real)0.2, (cloth_real)9.81, &b) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_cantilever_overhang((cloth_real)1e-5, 0, (cloth_real)9.81, &l) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_cantilever_overhang((cloth_real)-1e-5, (cloth_real)0.2, (cloth_real)9.81, &l) ==
           CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_bending_length((cloth_real)1e-5, (cloth_real)0.2, 0, &c) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_bending_length((cloth_real)1e-5, (cloth_real)INFINITY, (cloth_real)9.81, &c) == CLOTH_ERROR_NOT_FINITE);
}

/* ---- stable time step ---------------------------------------------------------------- */

/* The spectral radius of symplectic Euler with explicit damping on x'' + kappa x' + w^2 x = 0:
   v1 = (1 - h kappa) v0 - h w^2 x0, x1 = x0 + h v1. */
static double oscillator_radius(double w, double kappa, double h)
{
    double a = 1 - h * kappa, b = -h * w * w, c = h * (1 - h * kappa), d = 1 - h * h * w * w;
    double tr = a + d, det = a * d - b * c, disc = tr * tr - 4 * det;
    if (disc < 0) return sqrt(det);
    return 0.5 * (fabs(tr) + sqrt(disc));
}

TEST(explicit_limit_on_a_damped_oscillator)
{
    static const double rayleigh[4] = { 0, 1e-3, 1e-2, 0.1 };
    cloth_real h;
    int i;
    double w = 50;
    for (i = 0; i < 4; ++i) {
        double kappa = rayleigh[i] * w * w; /* a Rayleigh-damped mode */
        ENSURE(cloth_explicit_time_step_limit((cloth_real)w, (cloth_real)kappa, &h) == CLOTH_SUCCESS);
        ENSURE(oscillator_radius(w, kappa, (double)h * (1 - 1e-5)) <= 1 + 1e-9);
        ENSURE(oscillator_radius(w, kappa, (double)h * 1.01) > 1 + 1e-6);
    }
    ENSURE(cloth_explicit_time_step_limit((cloth_real)w, 0, &h) == CLOTH_SUCCESS && rel_err(h, 2 / w) < REL);
    ENSURE(cloth_explicit_time_step_limit(0, 8, &h) == CLOTH_SUCCESS && rel_err(h, 2.0 / 8) < REL);
    ENSURE(cloth_explicit_time_step_limit(0, 0, &h) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_explicit_time_step_limit(-1, 0, &h) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_explicit_time_step_limit((cloth_real)NAN, 0, &h) == CLOTH_ERROR_NOT_FINITE);
}

TEST(stability_length_of_triangles)
{
    cloth_rng rng = cloth_rng_make(31);
    cloth_real a[2], b[2], c[2];
    double s = 0.013;
    int i;
    a[0] = 0; a[1] = 0; b[0] = (cloth_real)s; b[1] = 0;
    c[0] = (cloth_real)(0.5 * s); c[1] = (cloth_real)(0.5 * sqrt(3.0) * s);
    ENSURE(rel_err(cloth_triangle_stability_length(a, b, c), s) < 10 * REL);
    c[0] = 0; c[1] = (cloth_real)s;
    ENSURE(rel_err(cloth_triangle_stability_length(a, b, c), s * sqrt(2.0 / 3.0)) < 10 * REL);
    ENSURE(rel_err(cloth_triangle_stability_length(a, c, b), s * sqrt(2.0 / 3.0)) < 10 * REL); /* either winding */
    c[0] = (cloth_real)(2 * s); c[1] = 0;
    ENSURE(cloth_triangle_stability_length(a, b, c) == 0); /* collinear */
    c[1] = (cloth_real)NAN;
    ENSURE(cloth_triangle_stability_length(a, b, c) == 0);
    for (i = 0; i < 50; ++i) {
        cloth_real p[3][2], q[3][2];
        double area, l, ang = 6.283185307179586 * cloth_rng_uniform(&rng), co = cos(ang), si = sin(ang);
        int k;
        for (k = 0; k < 3; ++k) {
            p[k][0] = (cloth_real)cloth_rng_uniform(&rng);
            p[k][1] = (cloth_real)cloth_rng_uniform(&rng);
            /* rotated, translated and scaled by 2 */
            q[k][0] = (cloth_real)(2 * (co * p[k][0] - si * p[k][1]) + 5);
            q[k][1] = (cloth_real)(2 * (si * p[k][0] + co * p[k][1]) - 3);
        }
        area = 0.5 * fabs(((double)p[1][0] - p[0][0]) * ((double)p[2][1] - p[0][1]) -
                          ((double)p[2][0] - p[0][0]) * ((double)p[1][1] - p[0][1]));
        if (area < 1e-3) continue;
        l = cloth_triangle_stability_length(p[0], p[1], p[2]);
        ENSURE(l > 0 && l * l <= 4 * area / sqrt(3.0) * (1 + 1e-5));
        ENSURE(rel_err(cloth_triangle_stability_length(q[0], q[1], q[2]), 2 * l) < 1e3 * REL);
    }
}

TEST(stable_step_scales_with_length_stiffness_and_mass)
{
    cloth_material m = cloth_default_material(), s;
    cloth_real h1, h2;
    m.bend_warp = m.bend_weft = 0;
    ENSURE(cloth_material_stable_time_step(&m, (cloth_real)0.01, &h1) == CLOTH_SUCCESS);
    ENSURE(cloth_material_stable_time_step(&m, (cloth_real)0.02, &h2) == CLOTH_SUCCESS);
    ENSURE(rel_err(h2, 2 * (double)h1) < 10 * REL); /* membrane: h ~ L */
    s = m;
    s.stretch_warp *= 4; s.stretch_weft *= 4; s.stretch_coupling *= 4; s.shear *= 4;
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.01, &h2) == CLOTH_SUCCESS);
    ENSURE(rel_err(h2, 0.5 * (double)h1) < 10 * REL); /* h ~ 1/sqrt(k) */
    s = m;
    s.areal_density *= 4;
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.01, &h2) == CLOTH_SUCCESS);
    ENSURE(rel_err(h2, 2 * (double)h1) < 10 * REL); /* h ~ sqrt(rho) */
    /* bending-dominated (a nearly slack membrane): h ~ L^2 */
    s = m;
    s.stretch_warp = s.stretch_weft = s.shear = (cloth_real)1e-9;
    s.stretch_coupling = 0;
    s.bend_warp = (cloth_real)1e-3;
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.01, &h1) == CLOTH_SUCCESS);
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.02, &h2) == CLOTH_SUCCESS);
    ENSURE(rel_err(h2, 4 * (double)h1) < 1e-4);
    /* damping only shortens the step; strong relative damping makes it ~ L^2 as well */
    s = m;
    s.damping_stiffness = (cloth_real)1e-5;
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.01, &h2) == CLOTH_SUCCESS);
    ENSURE(cloth_material_stable_time_step(&m, (cloth_real)0.01, &h1) == CLOTH_SUCCESS);
    ENSURE(h2 < h1);
    s = m;
    s.stretch_warp = s.stretch_weft = s.shear = (cloth_real)1e-9;
    s.stretch_coupling = 0;
    s.damping_relative = 10;
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.01, &h1) == CLOTH_SUCCESS);
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.02, &h2) == CLOTH_SUCCESS);
    ENSURE(rel_err(h2, 4 * (double)h1) < 1e-4);
    /* errors */
    ENSURE(cloth_material_stable_time_step(&m, 0, &h1) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_material_stable_time_step(&m, (cloth_real)NAN, &h1) == CLOTH_ERROR_NOT_FINITE);
    s = m;
    s.areal_density = 0;
    ENSURE(cloth_material_stable_time_step(&s, (cloth_real)0.01, &h1) == CLOTH_ERROR_INVALID_ARGUMENT);
}

/* In-plane linear elasticity of a flat mesh at rest, assembled here from the shape function
   gradients: f = -K u with u[2n] in-plane displacements. */
typedef struct plane_system {
    int32_t n, m;
    const int32_t *tri;
    double *grad;  /* 6 per triangle: grad N_0, grad N_1, grad N_2 */
    double *area;
    double *mass;  /* lumped: rho A / 3 per triangle vertex */
    double c11, c12, c22, c33;
} plane_system;

static void plane_force(const plane_system *s, const double *u, double *f)
{
    int32_t t, k;
    memset(f, 0, sizeof(double) * 2 * (size_t)s->n);
    for (t = 0; t < s->m; ++t) {
        const int32_t *v = s->tri + 3 * t;
        const double *g = s->grad + 6 * t;
        double h00 = 0, h01 = 0, h10 = 0, h11 = 0, e11, e22, gam, n11, n22, n12;
        for (k = 0; k < 3; ++k) {
            h00 += u[2 * v[k]] * g[2 * k]; h01 += u[2 * v[k]] * g[2 * k + 1];
            h10 += u[2 * v[k] + 1] * g[2 * k]; h11 += u[2 * v[k] + 1] * g[2 * k + 1];
        }
        e11 = h00; e22 = h11; gam = h01 + h10;
        n11 = s->c11 * e11 + s->c12 * e22; n22 = s->c12 * e11 + s->c22 * e22; n12 = s->c33 * gam;
        for (k = 0; k < 3; ++k) {
            f[2 * v[k]] -= s->area[t] * (n11 * g[2 * k] + n12 * g[2 * k + 1]);
            f[2 * v[k] + 1] -= s->area[t] * (n22 * g[2 * k + 1] + n12 * g[2 * k]);
        }
    }
}

TEST(stable_step_bounds_the_true_frequency_of_a_mesh)
{
    cloth_mesh mesh;
    cloth_material mat;
    int orientation;
    ENSURE(cloth_material_preset("denim_11oz", &mat) == CLOTH_SUCCESS); /* strongly orthotropic */
    mat.bend_warp = mat.bend_weft = 0; /* out-of-plane: no part of the in-plane test */
    ENSURE(cloth_mesh_grid(&mesh, 7, 6, (cloth_real)0.06, (cloth_real)0.05, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) ==
           CLOTH_SUCCESS);
    for (orientation = 0; orientation < 2; ++orientation) {
        /* the pattern at 0 and at 30 degrees to the grain */
        double ang = orientation ? 0.5235987755982988 : 0, co = cos(ang), si = sin(ang);
        int32_t n = mesh.vertex_count, m = mesh.triangle_count, t, i, k, step;
        cloth_real *uv = (cloth_real *)malloc(sizeof(cloth_real) * 2 * (size_t)n);
        double *grad = (double *)malloc(sizeof(double) * 6 * (size_t)m), *area = (double *)malloc(sizeof(double) * (size_t)m);
        double *mass = (double *)calloc((size_t)n, sizeof(double));
        double *x = (double *)malloc(sizeof(double) * 2 * (size_t)n), *y = (double *)malloc(sizeof(double) * 2 * (size_t)n);
        double *v = (double *)malloc(sizeof(double) * 2 * (size_t)n);
        double lambda = 0, omega, h_true, h_mesh = 1e30, u0 = 0, umax;
        plane_system s;
        cloth_rng rng = cloth_rng_make(41);
        int ok = uv && grad && area && mass && x && y && v;
        if (!ok) { free(uv); free(grad); free(area); free(mass); free(x); free(y); free(v); cloth_mesh_free(&mesh); }
        ENSURE(ok);
        for (i = 0; i < n; ++i) {
            uv[2 * i] = (cloth_real)(co * mesh.uv[2 * i] - si * mesh.uv[2 * i + 1]);
            uv[2 * i + 1] = (cloth_real)(si * mesh.uv[2 * i] + co * mesh.uv[2 * i + 1]);
        }
        for (t = 0; t < m; ++t) {
            const int32_t *tv = mesh.tri + 3 * t;
            const cloth_real *p0 = uv + 2 * tv[0], *p1 = uv + 2 * tv[1], *p2 = uv + 2 * tv[2];
            double d = ((double)p1[0] - p0[0]) * ((double)p2[1] - p0[1]) - ((double)p2[0] - p0[0]) * ((double)p1[1] - p0[1]);
            const cloth_real *pp[3];
            cloth_real h_tri, h_len;
            pp[0] = p0; pp[1] = p1; pp[2] = p2;
            area[t] = 0.5 * fabs(d);
            for (k = 0; k < 3; ++k) {
                const cloth_real *q = pp[(k + 1) % 3], *r = pp[(k + 2) % 3];
                grad[6 * t + 2 * k] = ((double)q[1] - r[1]) / d;
                grad[6 * t + 2 * k + 1] = ((double)r[0] - q[0]) / d;
                mass[tv[k]] += (double)mat.areal_density * area[t] / 3;
            }
            ENSURE(cloth_material_triangle_time_step(&mat, p0, p1, p2, &h_tri) == CLOTH_SUCCESS);
            ENSURE(cloth_material_stable_time_step(&mat, cloth_triangle_stability_length(p0, p1, p2), &h_len) ==
                   CLOTH_SUCCESS);
            ENSURE(h_len <= h_tri * (1 + 10 * REL)); /* the closed form is the looser bound */
            if (h_tri < h_mesh) h_mesh = h_tri;
        }
        s.n = n; s.m = m; s.tri = mesh.tri; s.grad = grad; s.area = area; s.mass = mass;
        s.c11 = mat.stretch_warp; s.c12 = mat.stretch_coupling; s.c22 = mat.stretch_weft; s.c33 = mat.shear;
        /* the largest eigenvalue of M^-1 K by power iteration on M^-1/2 K M^-1/2 */
        for (i = 0; i < 2 * n; ++i) x[i] = cloth_rng_uniform(&rng) - 0.5;
        for (step = 0; step < 4000; ++step) {
            double norm = 0;
            for (i = 0; i < 2 * n; ++i) v[i] = x[i] / sqrt(mass[i / 2]);
            plane_force(&s, v, y);
            for (i = 0; i < 2 * n; ++i) { y[i] = -y[i] / sqrt(mass[i / 2]); norm += y[i] * y[i]; }
            norm = sqrt(norm);
            lambda = 0;
            for (i = 0; i < 2 * n; ++i) lambda += x[i] * y[i];
            { double xx = 0; for (i = 0; i < 2 * n; ++i) xx += x[i] * x[i]; lambda /= xx; }
            for (i = 0; i < 2 * n; ++i) x[i] = y[i] / norm;
        }
        omega = sqrt(lambda);
        h_true = 2 / omega;
        ENSURE(h_mesh <= h_true * (1 + 1e-6));  /* sound */
        ENSURE(h_mesh >= 0.5 * h_true);        /* and not far below the truth */
        /* symplectic Euler below the bound stays bounded; just above the true limit it grows */
        for (k = 0; k < 2; ++k) {
            double h = k == 0 ? 0.999 * h_mesh : 1.02 * h_true;
            for (i = 0; i < 2 * n; ++i) { x[i] = 1e-4 * (cloth_rng_uniform(&rng) - 0.5); v[i] = 0; }
            u0 = 0;
            for (i = 0; i < 2 * n; ++i) u0 = fabs(x[i]) > u0 ? fabs(x[i]) : u0;
            umax = u0;
            for (step = 0; step < 3000 && umax < 1e6 * u0; ++step) {
                plane_force(&s, x, y);
                for (i = 0; i < 2 * n; ++i) {
                    v[i] += h * y[i] / mass[i / 2];
                    x[i] += h * v[i];
                    if (fabs(x[i]) > umax) umax = fabs(x[i]);
                }
            }
            if (k == 0) ENSURE(umax < 100 * u0);
            else ENSURE(umax >= 1e6 * u0);
        }
        free(uv); free(grad); free(area); free(mass); free(x); free(y); free(v);
    }
    cloth_mesh_free(&mesh);
}

/* The largest eigenvalue of M^-1 A for a symmetric positive semidefinite operator A on n
   scalar unknowns with diagonal M, by power iteration on M^-1/2 A M^-1/2. */
typedef void (*scalar_operator)(const void *context, const double *w, double *out);
static double largest_generalised_eigenvalue(scalar_operator apply, const void *context, const double *mass, int32_t n)
{
    double *x = (double *)malloc(sizeof(double) * (size_t)n), *y = (double *)malloc(sizeof(double) * (size_t)n);
    double *z = (double *)malloc(sizeof(double) * (size_t)n), lambda = -1;
    cloth_rng rng = cloth_rng_make(99);
    int32_t i;
    int step;
    if (x && y && z) {
        for (i = 0; i < n; ++i) x[i] = cloth_rng_uniform(&rng) - 0.5;
        for (step = 0; step < 6000; ++step) {
            double xy = 0, xx = 0, yy = 0;
            for (i = 0; i < n; ++i) z[i] = x[i] / sqrt(mass[i]);
            apply(context, z, y);
            for (i = 0; i < n; ++i) { y[i] /= sqrt(mass[i]); xy += x[i] * y[i]; xx += x[i] * x[i]; yy += y[i] * y[i]; }
            lambda = xy / xx;
            for (i = 0; i < n; ++i) x[i] = y[i] / sqrt(yy);
        }
    }
    free(x); free(y); free(z);
    return lambda;
}

/* Out-of-plane stiffness of the flat mesh under cloth.h's dihedral energy
   E = B l^2/(2 (a0 + a1)) theta^2 (the forces module's form), with theta linearised at the flat
   rest state: theta = sum_k c_k w_k over the stencil, c = ((1-t0)/h0 + (1-t1)/h1,
   t0/h0 + t1/h1, -1/h0, -1/h1); Hessian 2 B weight c c^T. */
typedef struct hinge_system { int32_t count; int32_t *vertex; double *coef; double *weight; double stiffness; } hinge_system;
static void hinge_apply(const void *context, const double *w, double *out)
{
    const hinge_system *s = (const hinge_system *)context;
    int32_t e, k, n = 0;
    for (e = 0; e < s->count; ++e) for (k = 0; k < 4; ++k) if (s->vertex[4 * e + k] + 1 > n) n = s->vertex[4 * e + k] + 1;
    memset(out, 0, sizeof(double) * (size_t)n);
    for (e = 0; e < s->count; ++e) {
        double theta = 0;
        for (k = 0; k < 4; ++k) theta += s->coef[4 * e + k] * w[s->vertex[4 * e + k]];
        for (k = 0; k < 4; ++k) out[s->vertex[4 * e + k]] += 2 * s->stiffness * s->weight[e] * theta * s->coef[4 * e + k];
    }
}

/* Seed 002's relative damping per triangle, f_a = -c sum_b (v_a - v_b), as the operator
   v -> -f on one velocity component. */
typedef struct damping_system { int32_t n, m; const int32_t *tri; double c; } damping_system;
static void damping_apply(const void *context, const double *v, double *out)
{
    const damping_system *s = (const damping_system *)context;
    int32_t t, a, b;
    memset(out, 0, sizeof(double) * (size_t)s->n);
    for (t = 0; t < s->m; ++t)
        for (a = 0; a < 3; ++a)
            for (b = 0; b < 3; ++b)
                if (a != b) out[s->tri[3 * t + a]] += s->c * (v[s->tri[3 * t + a]] - v[s->tri[3 * t + b]]);
}

static double point_line(const cloth_real *p, const cloth_real *a, const cloth_real *b, double *t)
{
    double ex = (double)b[0] - a[0], ey = (double)b[1] - a[1], px = (double)p[0] - a[0], py = (double)p[1] - a[1];
    double l2 = ex * ex + ey * ey;
    *t = (px * ex + py * ey) / l2;
    return fabs(ex * py - ey * px) / sqrt(l2);
}

TEST(stable_step_bounds_bending_and_relative_damping_of_a_mesh)
{
    cloth_mesh mesh;
    cloth_topology topo;
    cloth_material mat = cloth_default_material();
    hinge_system hs;
    damping_system ds;
    double *mass, *area, omega2, kappa, h_mesh;
    int32_t t, e, k, n, m;
    int pass;
    ENSURE(cloth_mesh_grid(&mesh, 9, 8, (cloth_real)0.08, (cloth_real)0.07, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) ==
           CLOTH_SUCCESS);
    ENSURE(cloth_topology_build(&topo, &mesh, NULL) == CLOTH_SUCCESS);
    n = mesh.vertex_count;
    m = mesh.triangle_count;
    mass = (double *)calloc((size_t)n, sizeof(double));
    area = (double *)malloc(sizeof(double) * (size_t)m);
    hs.vertex = (int32_t *)malloc(sizeof(int32_t) * 4 * (size_t)topo.edge_count);
    hs.coef = (double *)malloc(sizeof(double) * 4 * (size_t)topo.edge_count);
    hs.weight = (double *)malloc(sizeof(double) * (size_t)topo.edge_count);
    ENSURE(mass && area && hs.vertex && hs.coef && hs.weight);
    for (t = 0; t < m; ++t) {
        const cloth_real *p0 = mesh.uv + 2 * mesh.tri[3 * t], *p1 = mesh.uv + 2 * mesh.tri[3 * t + 1];
        const cloth_real *p2 = mesh.uv + 2 * mesh.tri[3 * t + 2];
        area[t] = 0.5 * fabs(((double)p1[0] - p0[0]) * ((double)p2[1] - p0[1]) - ((double)p2[0] - p0[0]) * ((double)p1[1] - p0[1]));
    }
    for (pass = 0; pass < 2; ++pass) {
        /* pass 0: bending alone; pass 1: relative damping alone (membrane nearly slack in both) */
        cloth_material s = mat;
        s.stretch_warp = s.stretch_weft = s.shear = (cloth_real)1e-6;
        s.stretch_coupling = 0;
        s.bend_warp = pass == 0 ? (cloth_real)2e-5 : 0;
        s.bend_weft = pass == 0 ? (cloth_real)1e-5 : 0;
        s.damping_relative = pass == 1 ? (cloth_real)0.02 : 0;
        memset(mass, 0, sizeof(double) * (size_t)n);
        h_mesh = 1e30;
        for (t = 0; t < m; ++t) {
            const int32_t *tv = mesh.tri + 3 * t;
            cloth_real h, h_len;
            for (k = 0; k < 3; ++k) mass[tv[k]] += (double)s.areal_density * area[t] / 3;
            ENSURE(cloth_material_triangle_time_step(&s, mesh.uv + 2 * tv[0], mesh.uv + 2 * tv[1], mesh.uv + 2 * tv[2],
                                                     &h) == CLOTH_SUCCESS);
            /* the closed form, from the triangle's stability length alone, is never larger */
            ENSURE(cloth_material_stable_time_step(&s, cloth_triangle_stability_length(mesh.uv + 2 * tv[0],
                   mesh.uv + 2 * tv[1], mesh.uv + 2 * tv[2]), &h_len) == CLOTH_SUCCESS);
            ENSURE(h_len <= h * (1 + 10 * REL));
            if (h < h_mesh) h_mesh = h;
        }
        if (pass == 0) {
            hs.count = 0;
            hs.stiffness = s.bend_warp > s.bend_weft ? s.bend_warp : s.bend_weft;
            for (e = 0; e < topo.edge_count; ++e) {
                int32_t i0 = topo.edge_vertex[2 * e], i1 = topo.edge_vertex[2 * e + 1];
                int32_t o0 = topo.edge_opposite[2 * e], o1 = topo.edge_opposite[2 * e + 1];
                const cloth_real *x0 = mesh.uv + 2 * i0, *x1 = mesh.uv + 2 * i1;
                double t0, t1, h0, h1, l2;
                if (o0 < 0 || o1 < 0) continue;
                h0 = point_line(mesh.uv + 2 * o0, x0, x1, &t0);
                h1 = point_line(mesh.uv + 2 * o1, x0, x1, &t1);
                l2 = ((double)x1[0] - x0[0]) * ((double)x1[0] - x0[0]) + ((double)x1[1] - x0[1]) * ((double)x1[1] - x0[1]);
                hs.vertex[4 * hs.count] = i0; hs.vertex[4 * hs.count + 1] = i1;
                hs.vertex[4 * hs.count + 2] = o0; hs.vertex[4 * hs.count + 3] = o1;
                hs.coef[4 * hs.count] = (1 - t0) / h0 + (1 - t1) / h1;
                hs.coef[4 * hs.count + 1] = t0 / h0 + t1 / h1;
                hs.coef[4 * hs.count + 2] = -1 / h0;
                hs.coef[4 * hs.count + 3] = -1 / h1;
                /* a0 + a1 = l (h0 + h1) / 2 */
                hs.weight[hs.count] = l2 / (2 * (0.5 * sqrt(l2) * (h0 + h1)));
                hs.count++;
            }
            omega2 = largest_generalised_eigenvalue(hinge_apply, &hs, mass, n);
            ENSURE(omega2 > 0);
            /* the bending term is an estimate: it must still bound this regular mesh, and not
               by a wide margin */
            ENSURE(h_mesh <= 2 / sqrt(omega2));
            ENSURE(h_mesh >= 0.4 * 2 / sqrt(omega2));
        } else {
            ds.n = n; ds.m = m; ds.tri = mesh.tri; ds.c = s.damping_relative;
            kappa = largest_generalised_eigenvalue(damping_apply, &ds, mass, n);
            ENSURE(kappa > 0);
            /* pure damping under symplectic Euler: v <- (1 - h kappa) v, stable for h kappa <= 2 */
            ENSURE(h_mesh <= 2 / kappa * (1 + 1e-9));
            ENSURE(h_mesh >= 0.4 * 2 / kappa);
        }
    }
    free(mass); free(area); free(hs.vertex); free(hs.coef); free(hs.weight);
    cloth_topology_free(&topo);
    cloth_mesh_free(&mesh);
}

TEST(triangle_step_rejects_bad_input)
{
    cloth_material m = cloth_default_material();
    cloth_real a[2], b[2], c[2], h;
    a[0] = 0; a[1] = 0; b[0] = (cloth_real)0.01; b[1] = 0; c[0] = (cloth_real)0.02; c[1] = 0;
    ENSURE(cloth_material_triangle_time_step(&m, a, b, c, &h) == CLOTH_ERROR_DEGENERATE_TRIANGLE);
    c[1] = (cloth_real)INFINITY;
    ENSURE(cloth_material_triangle_time_step(&m, a, b, c, &h) == CLOTH_ERROR_NOT_FINITE);
    c[0] = 0; c[1] = (cloth_real)0.01;
    ENSURE(cloth_material_triangle_time_step(&m, a, b, c, &h) == CLOTH_SUCCESS && h > 0);
    m.stretch_coupling = m.stretch_warp * 2;
    ENSURE(cloth_material_triangle_time_step(&m, a, b, c, &h) == CLOTH_ERROR_INVALID_ARGUMENT);
}

const test_case material_tests[] = {
    { "default_is_a_valid_midweight_cotton", default_is_a_valid_midweight_cotton },
    { "validate_rejects_non_physical_values", validate_rejects_non_physical_values },
    { "isotropic_membrane_relations", isotropic_membrane_relations },
    { "orthotropic_engineering_round_trip_and_uniaxial_test", orthotropic_engineering_round_trip_and_uniaxial_test },
    { "lame_membrane_is_isotropic_stvk", lame_membrane_is_isotropic_stvk },
    { "seed002_fit_reading", seed002_fit_reading },
    { "arcsim_reading_reproduces_arcsim_energies", arcsim_reading_reproduces_arcsim_energies },
    { "measured_presets_agree_with_the_notes", measured_presets_agree_with_the_notes },
    { "presets_enumerate_and_look_up_by_name", presets_enumerate_and_look_up_by_name },
    { "kes_units_from_their_definitions", kes_units_from_their_definitions },
    { "kes_tensile_worked_example", kes_tensile_worked_example },
    { "kes_measurement_to_material", kes_measurement_to_material },
    { "cantilever_worked_example", cantilever_worked_example },
    { "explicit_limit_on_a_damped_oscillator", explicit_limit_on_a_damped_oscillator },
    { "stability_length_of_triangles", stability_length_of_triangles },
    { "stable_step_scales_with_length_stiffness_and_mass", stable_step_scales_with_length_stiffness_and_mass },
    { "stable_step_bounds_the_true_frequency_of_a_mesh", stable_step_bounds_the_true_frequency_of_a_mesh },
    { "stable_step_bounds_bending_and_relative_damping_of_a_mesh", stable_step_bounds_bending_and_relative_damping_of_a_mesh },
    { "triangle_step_rejects_bad_input", triangle_step_rejects_bad_input },
    { NULL, NULL }
};
