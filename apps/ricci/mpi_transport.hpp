#pragma once
/// \file
/// The MPI calls of `ricci batch` under mpirun (batch_mpi.cpp), in a module of their own
/// (ricci-mpi.so, built from mpi_transport.cpp when CMake finds MPI) that the program loads only
/// when an MPI launcher started it: Open MPI's libraries (some 6, 1.4 ms of every start) stay out
/// of every other run, and the program runs where Open MPI is not installed. A C interface, so
/// that nothing of the C++ ABI crosses it.

extern "C" {

/// Transport between ranks: bytes with a tag, on MPI_COMM_WORLD.
struct RicciMpiTransport {
  /// kRicciMpiTransportVersion of the module's build; the program refuses another.
  int version;
  void (*init)();
  void (*finalize)();
  int (*rank)();
  int (*size)();
  void (*send)(const char* data, int size, int destination, int tag);
  /// Without blocking: 1 when a message from `source` (-1: any) with `tag` (-1: any) has
  /// arrived, with its source, tag and size; 0 otherwise.
  int (*probe)(int source, int tag, int* found_source, int* found_tag, int* found_size);
  /// The probed message (size bytes into data).
  void (*receive)(char* data, int size, int source, int tag);
};

/// The module's one exported symbol.
const RicciMpiTransport* ricci_mpi_transport();
using RicciMpiTransportEntry = const RicciMpiTransport* (*)();
}

/// Raised whenever the structure above changes.
inline constexpr int kRicciMpiTransportVersion = 1;
