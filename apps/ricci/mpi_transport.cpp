// The MPI module (mpi_transport.hpp): Open MPI's C API behind RicciMpiTransport.
#include "mpi_transport.hpp"

#include <mpi.h>

namespace {

void init() {
  MPI_Init(nullptr, nullptr);
}

void finalize() {
  MPI_Finalize();
}

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

void send(const char* data, int count, int destination, int tag) {
  MPI_Send(data, count, MPI_CHAR, destination, tag, MPI_COMM_WORLD);
}

int probe(int source, int tag, int* found_source, int* found_tag, int* found_size) {
  MPI_Status status;
  int flag = 0;
  MPI_Iprobe(source < 0 ? MPI_ANY_SOURCE : source, tag < 0 ? MPI_ANY_TAG : tag, MPI_COMM_WORLD,
             &flag, &status);
  if (!flag) return 0;
  *found_source = status.MPI_SOURCE;
  *found_tag = status.MPI_TAG;
  MPI_Get_count(&status, MPI_CHAR, found_size);
  return 1;
}

void receive(char* data, int count, int source, int tag) {
  MPI_Recv(data, count, MPI_CHAR, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

const RicciMpiTransport kTransport = {
    kRicciMpiTransportVersion, init, finalize, rank, size, send, probe, receive};

}  // namespace

extern "C" __attribute__((visibility("default"))) const RicciMpiTransport* ricci_mpi_transport() {
  return &kTransport;
}
