// Times OpenMesh's uniform Loop subdivider (OpenMesh::Subdivider::Uniform::LoopT)
// on one OBJ file: one timed call per process, as the interleaved comparison
// (run.sh, compare.py) runs it. Reading the file is not timed.
//
// Build (as CMake's Release build type does: -O2 -DNDEBUG; without -DNDEBUG
// OpenMesh's assertions stay on, among them a full mesh check per round):
//   g++ -std=c++17 -O2 -DNDEBUG om_loop.cpp -lOpenMeshTools -lOpenMeshCore -o om_loop
// Run: ./om_loop MESH.obj ROUNDS
// Prints one line: wall_ms=... cpu_ms=... faces=... maxrss_kb=...

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <sys/resource.h>
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

typedef OpenMesh::TriMesh_ArrayKernelT<> Mesh;

static double cpu_ms() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: om_loop MESH.obj ROUNDS\n");
        return 2;
    }
    const int rounds = std::atoi(argv[2]);
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
        std::fprintf(stderr, "om_loop: cannot read %s\n", argv[1]);
        return 1;
    }
    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = cpu_ms();
    {
        OpenMesh::Subdivider::Uniform::LoopT<Mesh> loop;
        loop.attach(mesh);
        loop(rounds);
        loop.detach();
    }
    const double cpu = cpu_ms() - cpu0;
    const double wall =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
    rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    std::printf("wall_ms=%.3f cpu_ms=%.3f faces=%zu maxrss_kb=%ld\n", wall, cpu, mesh.n_faces(),
                usage.ru_maxrss);
    return 0;
}
