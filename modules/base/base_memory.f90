!> How the C library's allocator treats the large blocks a run frees. An
!> Euler step allocates its work arrays (some hundred doubles per cell of
!> the grid) and frees them at its end. By default glibc gives such blocks
!> back to the system (a block above its mmap threshold is unmapped, the
!> heap's free top is trimmed), so the next Euler step faults every page in
!> again and the kernel zero-fills it: on Sedov 40^3 with LSSM that was a
!> tenth of the Euler phase. Kept (no trimming; mmap only for blocks above
!> 32 MiB, the largest threshold glibc accepts on 64-bit), freed blocks
!> are reused by the next step. The process then keeps its peak memory
!> rather than shrinking between steps; blocks above 32 MiB (grids beyond
!> about a million cells) are still mapped and unmapped each time.
!>
!> `memory_peak_mib`: the process's peak resident memory so far (Linux's
!> VmHWM), for the log.
module base_memory
  use, intrinsic :: iso_c_binding, only: c_int
  use base_kinds, only: i8
  implicit none
  private
  public :: memory_keep_freed, memory_peak_mib

  !> glibc's malloc.h: mallopt parameters
  integer(c_int), parameter :: M_TRIM_THRESHOLD = -1_c_int, M_MMAP_THRESHOLD = -3_c_int

  interface
    !> glibc: sets an allocator parameter; 1 on success, 0 on error.
    integer(c_int) function mallopt(param, value) bind(C, name='mallopt')
      import :: c_int
      integer(c_int), value :: param, value
    end function mallopt
  end interface

contains

  !> Keeps freed blocks for reuse (see the module's note). A C library
  !> that refuses a setting keeps its default: the run is the same, only
  !> slower.
  subroutine memory_keep_freed()
    integer(c_int) :: ok
    ok = mallopt(M_MMAP_THRESHOLD, 33554432_c_int)
    ok = mallopt(M_TRIM_THRESHOLD, huge(1_c_int))
  end subroutine memory_keep_freed

  !> The peak resident memory of this process so far in MiB (VmHWM of
  !> /proc/self/status); -1 where that cannot be read.
  integer function memory_peak_mib() result(mib)
    character(len=256) :: line
    integer(i8) :: kib
    integer :: u, ios
    mib = -1
    open(newunit=u, file='/proc/self/status', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:6) /= 'VmHWM:') cycle
      read(line(7:), *, iostat=ios) kib
      if (ios == 0) mib = int((kib + 1023_i8)/1024_i8)
      exit
    end do
    close(u)
  end function memory_peak_mib
end module base_memory
