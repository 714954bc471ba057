// carve command line: a thin layer over the library (placeholder until the pipeline lands).
#include <cstdio>

int main() {
    std::fputs("carve: pipeline not assembled yet\n", stderr);
    return 1;
}
