#include "app/cli.hpp"

int main(int argc, char** argv) { return inkline::run_cli(argc, argv); }
