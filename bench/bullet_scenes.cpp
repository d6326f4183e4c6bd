// Peer measurements for cloth.h: the standard "hang" and "sphere" scenes of
// docs/scenes.md run in Bullet's position-based soft body (btSoftBody in a
// btSoftRigidDynamicsWorld, single thread).
//
// Usage: bullet_scenes SCENE BENDING RUNS N...
//   SCENE is hang or sphere; BENDING is 0 (stretch links only) or the distance given to
//   btSoftBody::generateBendingConstraints (2: the usual cloth set-up of Bullet's demos,
//   extra links between vertices two edges apart, same material, kLST = 1).
// Prints a CSV header and one row per n on stdout; progress goes to stderr.
// bench/bullet.sh builds this and adds the machine and CPU columns.
//
// Bullet settings (docs/scenes.md's reference configuration):
//   4 substeps per frame: stepSimulation(1/60, 4, 1/240), the ordinary fixed-step call;
//   m_cfg.piterations = 10 (position solver iterations), everything else at Bullet's defaults
//   (viterations 0, diterations 0, citerations 4, kDP 0, kDF 0.2 unless set below,
//   kKHR 0.1, no aerodynamics);
//   soft body collision margin 0.01 m (Bullet's default is 0.25 m);
//   material m_kLST = 1 (stiff stretch links; also Bullet's default), m_kAST = m_kVST = 1;
//   CreatePatch with gendiags = true: structural links plus one diagonal link per quad,
//   the same edges as the patch's triangles, so "edges" below are those links (the mesh
//   edges); bending links, when asked for, come after them and are not counted as edges.
// Mass: 0.1 kg/m^2 lumped on the grid (h^2 * 0.1 per interior vertex, half that on the
//   borders, a quarter at the corners: 0.1 kg in all), then the pinned corners get mass 0.
// sphere: btSphereShape(0.3) on a static rigid body (mass 0) at the origin, friction 0.5.
//   Bullet's node-vs-rigid friction is kDF * body friction, so kDF = 1 and the body's
//   friction 0.5 give 0.5. Contacts use Bullet's default SDF_RS (a sparse signed distance
//   field sampled from the shape). Soft-body self-collision (VF_SS) is not run by Bullet
//   3.24 for a body against itself, so it is not requested here.
//
// Timing: each run builds a fresh world (setup timed apart) and steps the whole scene;
// the step loop is timed with nothing else in it (wall clock and thread CPU time).
// Metrics: one more run, identical but stepped one substep at a time with
// stepSimulation(1/240, 0), measures after every substep: max edge strain
// (max over mesh edges of |e|/|e_rest| - 1), lowest y, and for the sphere the penetration
// max over vertices of (0.3 - |x_i|). Its final positions are compared with the last
// timed run's (column check_dx_m) to show both ran the same simulation. The last column,
// cpu_ms_median_frame, is the median frame of each timed run by the thread's CPU clock (read
// around every frame), the median over the runs: the statistic bench/stress reports for
// cloth.h (ms_per_frame_median is the run's mean frame, the median over the runs).

#include <btBulletDynamicsCommon.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <LinearMath/btScalar.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

namespace {

const double kFps = 60.0;
const int kSubsteps = 4;
const int kPIterations = 10;
const double kMargin = 0.01;
const double kDensity = 0.1;  // kg/m^2
const double kGravity = -9.81;
const double kSphereRadius = 0.3;
const double kFriction = 0.5;

struct Sim {
    btSoftBodyRigidBodyCollisionConfiguration* config = nullptr;
    btCollisionDispatcher* dispatcher = nullptr;
    btBroadphaseInterface* broadphase = nullptr;
    btSequentialImpulseConstraintSolver* solver = nullptr;
    btSoftRigidDynamicsWorld* world = nullptr;
    btSoftBody* cloth = nullptr;
    btCollisionShape* sphere_shape = nullptr;
    btDefaultMotionState* sphere_motion = nullptr;
    btRigidBody* sphere = nullptr;
    long substeps = 0;  // counted by a pre-tick callback
};

void count_tick(btDynamicsWorld* world, btScalar) {
    static_cast<Sim*>(world->getWorldUserInfo())->substeps++;
}

double now_s(clockid_t clock) {
    timespec t;
    clock_gettime(clock, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

Sim* create(int n, bool with_sphere, int bending) {
    Sim* s = new Sim;
    s->config = new btSoftBodyRigidBodyCollisionConfiguration();
    s->dispatcher = new btCollisionDispatcher(s->config);
    s->broadphase = new btDbvtBroadphase();
    s->solver = new btSequentialImpulseConstraintSolver();
    s->world = new btSoftRigidDynamicsWorld(s->dispatcher, s->broadphase, s->solver, s->config);
    const btVector3 g(0, btScalar(kGravity), 0);
    s->world->setGravity(g);
    btSoftBodyWorldInfo& info = s->world->getWorldInfo();
    info.m_gravity = g;  // the soft body reads gravity from here, not from the world
    info.m_sparsesdf.Initialize();
    s->world->setInternalTickCallback(count_tick, s, true);

    // Corner00 and corner10 are the two corners at z = -0.5 (fixeds bits 1 and 2).
    // Node (ix, iz) is index iz * n + ix, at x = -0.5 + ix h, z = -0.5 + iz h.
    const int pins = with_sphere ? 0 : (1 | 2);
    btSoftBody* c = btSoftBodyHelpers::CreatePatch(
        info, btVector3(-0.5, 1, -0.5), btVector3(0.5, 1, -0.5), btVector3(-0.5, 1, 0.5),
        btVector3(0.5, 1, 0.5), n, n, pins, true);
    const double h = 1.0 / (n - 1);
    for (int iz = 0; iz < n; ++iz) {
        for (int ix = 0; ix < n; ++ix) {
            const int i = iz * n + ix;
            double m = kDensity * h * h;
            if (ix == 0 || ix == n - 1) m *= 0.5;
            if (iz == 0 || iz == n - 1) m *= 0.5;
            if (c->m_nodes[i].m_im > 0) c->setMass(i, btScalar(m));  // pinned ones stay 0
        }
    }
    btSoftBody::Material* mat = c->m_materials[0];
    mat->m_kLST = 1;
    mat->m_kAST = 1;
    mat->m_kVST = 1;
    c->m_cfg.piterations = kPIterations;
    c->getCollisionShape()->setMargin(btScalar(kMargin));
    if (with_sphere) c->m_cfg.kDF = 1;  // times the sphere's friction 0.5
    if (bending > 0) c->generateBendingConstraints(bending, mat);
    s->world->addSoftBody(c);
    s->cloth = c;

    if (with_sphere) {
        s->sphere_shape = new btSphereShape(btScalar(kSphereRadius));
        btTransform t;
        t.setIdentity();
        s->sphere_motion = new btDefaultMotionState(t);
        btRigidBody::btRigidBodyConstructionInfo ci(0, s->sphere_motion, s->sphere_shape);
        ci.m_friction = btScalar(kFriction);
        s->sphere = new btRigidBody(ci);
        s->world->addRigidBody(s->sphere);
    }
    return s;
}

void destroy(Sim* s) {
    if (s->sphere) {
        s->world->removeRigidBody(s->sphere);
        delete s->sphere;
        delete s->sphere_motion;
        delete s->sphere_shape;
    }
    s->world->removeSoftBody(s->cloth);
    delete s->cloth;
    delete s->world;
    delete s->solver;
    delete s->broadphase;
    delete s->dispatcher;
    delete s->config;
    delete s;
}

struct Metrics {
    double strain_run = -1e30;  // max over substeps of the max edge strain
    double strain_end = 0;
    double strain_end_x = 0, strain_end_z = 0;  // rest midpoint of that edge
    double lowest_y = 1e30;
    double penetration_run = -1e30;
    double penetration_end = 0;
    bool finite = true;
};

// Max edge strain now; *at gets the index of the link.
double max_strain(const btSoftBody* c, const std::vector<double>& rest, int* at) {
    double worst = -1e30;
    for (int i = 0; i < int(rest.size()); ++i) {
        const btSoftBody::Link& l = c->m_links[i];
        const btVector3 d = l.m_n[0]->m_x - l.m_n[1]->m_x;
        const double len = std::sqrt(double(d.x()) * d.x() + double(d.y()) * d.y() +
                                     double(d.z()) * d.z());
        const double e = len / rest[i] - 1;
        if (!(e <= worst)) {  // also takes NaN, so a blow-up shows
            worst = e;
            *at = i;
        }
    }
    return worst;
}

void measure(const Sim* s, const std::vector<double>& rest, bool end, Metrics* m) {
    const btSoftBody* c = s->cloth;
    int at = 0;
    const double strain = max_strain(c, rest, &at);
    if (!std::isfinite(strain)) m->finite = false;
    m->strain_run = std::max(m->strain_run, strain);
    double pen = -1e30;
    for (int i = 0; i < c->m_nodes.size(); ++i) {
        const btVector3& x = c->m_nodes[i].m_x;
        if (!std::isfinite(double(x.x())) || !std::isfinite(double(x.y())) ||
            !std::isfinite(double(x.z())))
            m->finite = false;
        m->lowest_y = std::min(m->lowest_y, double(x.y()));
        if (s->sphere) {
            const double r = std::sqrt(double(x.x()) * x.x() + double(x.y()) * x.y() +
                                       double(x.z()) * x.z());
            pen = std::max(pen, kSphereRadius - r);
        }
    }
    if (s->sphere) m->penetration_run = std::max(m->penetration_run, pen);
    if (end) {
        m->strain_end = strain;
        m->penetration_end = pen;
        // rest midpoint: the patch starts flat, so the rest positions are the grid's
        const btSoftBody::Link& l = c->m_links[at];
        const int a = int(l.m_n[0] - &c->m_nodes[0]), b = int(l.m_n[1] - &c->m_nodes[0]);
        const int n = int(std::lround(std::sqrt(double(c->m_nodes.size()))));
        const double h = 1.0 / (n - 1);
        m->strain_end_x = -0.5 + 0.5 * h * (a % n + b % n);
        m->strain_end_z = -0.5 + 0.5 * h * (a / n + b / n);
    }
}

// Rest lengths of the mesh edges: the links before any bending link.
std::vector<double> rest_lengths(const btSoftBody* c) {
    std::vector<double> rest;
    for (int i = 0; i < c->m_links.size() && !c->m_links[i].m_bbending; ++i)
        rest.push_back(c->m_links[i].m_rl);
    return rest;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t k = v.size();
    return k % 2 ? v[k / 2] : 0.5 * (v[k / 2 - 1] + v[k / 2]);
}

void usage() {
    std::fprintf(stderr, "usage: bullet_scenes hang|sphere BENDING RUNS N...\n");
    std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 5) usage();
    const std::string scene = argv[1];
    if (scene != "hang" && scene != "sphere") usage();
    const bool with_sphere = scene == "sphere";
    const int bending = std::atoi(argv[2]);
    if (bending < 0 || bending == 1) usage();
    const int runs = std::atoi(argv[3]);
    if (runs < 1) usage();
    const double seconds = with_sphere ? 3.0 : 2.0;
    const int frames = int(std::lround(seconds * kFps));
    const btScalar frame_dt = btScalar(1.0 / kFps);
    const btScalar sub_dt = btScalar(1.0 / (kFps * kSubsteps));

    std::printf(
        "scene,n,vertices,edges,bending_distance,links,bullet_version,scalar_bytes,"
        "substeps_per_frame,piterations,kLST,margin_m,friction,cloth_mass_kg,frames,runs,setup_ms,ms_per_frame_median,"
        "ms_per_frame_min,ms_per_frame_max,cpu_ms_per_frame_median,substeps_counted,"
        "max_strain_end,max_strain_run,max_strain_end_rest_x,max_strain_end_rest_z,lowest_y,"
        "penetration_max_m,penetration_end_m,finite,check_dx_m,cpu_ms_median_frame\n");
    std::fflush(stdout);

    for (int a = 4; a < argc; ++a) {
        const int n = std::atoi(argv[a]);
        if (n < 2) usage();
        std::vector<double> setup_ms, wall_ms, cpu_ms, median_frame_ms, frame_ms(frames);
        long substeps_timed = -1;
        std::vector<btVector3> timed_end;
        double mass = 0;
        int links = 0, edges = 0;
        for (int r = 0; r < runs; ++r) {
            const double t0 = now_s(CLOCK_MONOTONIC);
            Sim* s = create(n, with_sphere, bending);
            const double t1 = now_s(CLOCK_MONOTONIC);
            const double c1 = now_s(CLOCK_THREAD_CPUTIME_ID);
            double c_frame = c1;
            for (int f = 0; f < frames; ++f) {
                s->world->stepSimulation(frame_dt, kSubsteps, sub_dt);
                s->world->getWorldInfo().m_sparsesdf.GarbageCollect();  // as Bullet's demos do
                const double c_next = now_s(CLOCK_THREAD_CPUTIME_ID);
                frame_ms[f] = 1e3 * (c_next - c_frame);
                c_frame = c_next;
            }
            const double c2 = now_s(CLOCK_THREAD_CPUTIME_ID);
            median_frame_ms.push_back(median(frame_ms));
            const double t2 = now_s(CLOCK_MONOTONIC);
            setup_ms.push_back(1e3 * (t1 - t0));
            wall_ms.push_back(1e3 * (t2 - t1) / frames);
            cpu_ms.push_back(1e3 * (c2 - c1) / frames);
            if (substeps_timed >= 0 && substeps_timed != s->substeps)
                std::fprintf(stderr, "bullet_scenes: substep count differs between runs\n");
            substeps_timed = s->substeps;
            mass = s->cloth->getTotalMass();
            links = s->cloth->m_links.size();
            edges = int(rest_lengths(s->cloth).size());
            timed_end.clear();
            for (int i = 0; i < s->cloth->m_nodes.size(); ++i)
                timed_end.push_back(s->cloth->m_nodes[i].m_x);
            destroy(s);
            std::fprintf(stderr,
                         "bullet %s n=%d bending=%d run %d/%d: %.2f ms/frame (cpu %.2f), "
                         "setup %.1f ms\n",
                         scene.c_str(), n, bending, r + 1, runs, wall_ms.back(), cpu_ms.back(),
                         setup_ms.back());
        }

        // The measured run: same simulation, one substep per call, metrics after each.
        Sim* s = create(n, with_sphere, bending);
        const std::vector<double> rest = rest_lengths(s->cloth);
        Metrics m;
        for (int f = 0; f < frames; ++f) {
            for (int k = 0; k < kSubsteps; ++k) {
                s->world->stepSimulation(sub_dt, 0);
                measure(s, rest, f == frames - 1 && k == kSubsteps - 1, &m);
            }
            s->world->getWorldInfo().m_sparsesdf.GarbageCollect();
        }
        double dx = 0;
        for (int i = 0; i < s->cloth->m_nodes.size(); ++i)
            dx = std::max(dx, double((s->cloth->m_nodes[i].m_x - timed_end[i]).length()));
        destroy(s);

        const double pmax = *std::max_element(wall_ms.begin(), wall_ms.end());
        const double pmin = *std::min_element(wall_ms.begin(), wall_ms.end());
        std::printf("%s,%d,%d,%d,%d,%d,%d.%02d,%d,%d,%d,1,%g,", scene.c_str(), n, n * n,
                    edges, bending, links, btGetVersion() / 100, btGetVersion() % 100, int(sizeof(btScalar)),
                    kSubsteps, kPIterations, kMargin);
        if (with_sphere) std::printf("%g,", kFriction); else std::printf(",");
        std::printf("%.6f,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%ld,%.6f,%.6f,%.4f,%.4f,%.6f,",
                    mass, frames, runs, median(setup_ms), median(wall_ms), pmin, pmax,
                    median(cpu_ms), substeps_timed, m.strain_end, m.strain_run,
                    m.strain_end_x, m.strain_end_z, m.lowest_y);
        if (with_sphere) std::printf("%.6f,%.6f,", m.penetration_run, m.penetration_end);
        else std::printf(",,");
        std::printf("%d,%.3g,%.3f\n", m.finite ? 1 : 0, dx, median(median_frame_ms));
        std::fflush(stdout);
    }
    return 0;
}
