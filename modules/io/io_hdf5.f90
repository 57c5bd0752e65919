!> Thin HDF5 layer: files, numeric and string datasets, with errors returned
!> through `error_t` (HDF5's own error-stack printing is switched off).
!>
!> Array dimensions are given and returned in Fortran order; the HDF5 Fortran
!> API stores them reversed, so h5dump shows C order. Dataset names may contain
!> a group path ("state/rho"): missing intermediate groups are created on
!> write. Writing a dataset that already exists is an error.
!>
!> Checksummed files (`h5_create(..., checksums=.true.)`, used for restarts):
!> the file is written in the newest format of the library (HDF5 1.10), whose
!> superblock, object headers, group indexes and chunk indexes all carry
!> checksums, and every dataset that holds data carries HDF5's Fletcher-32
!> checksum of its data. The filter needs a chunked layout: an array is cut
!> along its last dimension into chunks of at most 1 MiB (in a file of
!> several ranks HDF5 gives each chunk to one rank, which checksums and
!> writes it: with one chunk per array a dump of 512 000 cells took 0.75 s
!> on 2 ranks, with chunks of 1 MiB 0.4-0.5 s; one process: 0.07-0.3 s),
!> a scalar (number or string) is stored as a one-element chunked
!> array (the readers of scalars accept both), and a zero-size array is left
!> contiguous, as it has no data to checksum (its shape is metadata, covered
!> by the object header's checksum). HDF5 verifies the checksum on every
!> read; a mismatch makes the read fail and the reader returns an error naming
!> the dataset. Frames are written without checksums (h5py, ParaView).
!>
!> Storage options of the array writers (frames, `&output precision` and
!> `compress`): `single` stores a double array as float32 (H5T_NATIVE_FLOAT
!> in the file); the values are converted here, before HDF5 sees them (round
!> to nearest, as numpy's float32(); beyond the float32 range +-infinity), so
!> the memory and file types agree and a file of several ranks keeps its
!> collective writes (HDF5 1.10 falls back to independent I/O for a write
!> that converts types, and refuses independent writes to a filtered
!> dataset). `deflate` = 1..9 compresses a dataset (byte shuffle, then
!> deflate at that level) in chunks cut as the checksums' are (1 MiB along
!> the last dimension); a zero-size array and a scalar stay contiguous. Both
!> filters run in collective writes of several ranks (parallel HDF5 >= 1.10.2;
!> Debian 12 has 1.10.8).
!>
!> The library's own exit handler is switched off (`hdf5_start`): after a
!> failed H5Fclose (a full disk) HDF5 1.10 keeps an identifier to a file it
!> has already freed, and its exit handler then crashes (exit 139). Every
!> routine here closes what it opens, so a file identifier still open when
!> the run ends is such a remnant: `hdf5_stop` then leaves the library alone
!> (the OS closes the file at exit), and closes it otherwise. The driver calls
!> it at the end of a run and on its failure path.
module io_hdf5
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_null_ptr, c_associated, c_f_pointer, c_null_char, &
                                         c_int, c_int64_t, c_intptr_t, &
                                         c_long, c_char
  use, intrinsic :: iso_fortran_env, only: int64, real32
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_is_nan, ieee_positive_inf, ieee_negative_inf, &
                                           ieee_quiet_nan
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_strings, only: itoa
  use hdf5, only: hid_t, hsize_t, size_t, &
       h5open_f, h5close_f, h5eset_auto_f, h5kind_to_type, h5get_libversion_f, h5dont_atexit_f, &
       H5_REAL_KIND, H5_INTEGER_KIND, &
       h5fcreate_f, h5fopen_f, h5fclose_f, h5fflush_f, h5fis_hdf5_f, H5F_OBJ_ALL_F, H5F_OBJ_FILE_F, &
       H5F_ACC_TRUNC_F, H5F_ACC_RDONLY_F, H5F_SCOPE_GLOBAL_F, &
       h5screate_f, h5screate_simple_f, h5sclose_f, h5sget_simple_extent_type_f, &
       h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, &
       h5sget_simple_extent_npoints_f, H5S_SCALAR_F, &
       h5tcopy_f, h5tclose_f, h5tset_size_f, h5tget_size_f, h5tset_strpad_f, &
       h5tget_class_f, h5tis_variable_str_f, &
       H5T_FORTRAN_S1, H5T_STR_NULLPAD_F, H5T_STRING_F, H5T_FLOAT_F, H5T_INTEGER_F, &
       h5pcreate_f, h5pclose_f, h5pset_create_inter_group_f, H5P_LINK_CREATE_F, &
       H5P_DATASET_CREATE_F, H5P_FILE_ACCESS_F, h5pset_chunk_f, h5pset_fletcher32_f, &
       h5pset_shuffle_f, h5pset_deflate_f, &
       h5pset_libver_bounds_f, H5F_LIBVER_LATEST_F, &
       h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, h5dread_f, &
       h5dget_space_f, h5dget_type_f, &
       h5gcreate_f, h5gclose_f, h5lexists_f, &
       h5pset_fapl_mpio_f, h5pset_dxpl_mpio_f, H5FD_MPIO_COLLECTIVE_F, H5P_DATASET_XFER_F, &
       h5sselect_none_f, h5sselect_hyperslab_f, H5S_SELECT_SET_F, H5S_SELECT_OR_F
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Comm_size, MPI_INFO_NULL, MPI_Allreduce, MPI_LOGICAL, MPI_LOR
  implicit none
  private

  public :: h5_file_t
  public :: hdf5_start, hdf5_stop, hdf5_version
  public :: h5_create, h5_open_read, h5_close
  public :: h5_create_group, h5_exists
  public :: h5_write_real, h5_write_int, h5_write_part_real, h5_write_part_int
  public :: h5_write_scalar_real, h5_write_scalar_int, h5_write_string
  public :: h5_read_dims, h5_read_real, h5_read_int
  public :: h5_read_scalar_real, h5_read_scalar_int, h5_read_string
  public :: h5_write_attribute, h5_write_attribute_string, h5_write_attribute_real, &
            h5_write_attribute_int, h5_read_attribute_string

  !> Writes an attribute on the file's root group or on a dataset or group.
  interface h5_write_attribute
    module procedure h5_write_attribute_string, h5_write_attribute_real, h5_write_attribute_int
  end interface h5_write_attribute

  !> An open HDF5 file: its identifier (negative when closed), its path,
  !> whether its datasets are written with checksums, and for a file written
  !> by several MPI ranks together (`h5_create` with `comm`) this rank.
  type :: h5_file_t
    integer(hid_t) :: id = -1_hid_t
    character(len=:), allocatable :: path
    logical :: checksums = .false.
    logical :: parallel = .false.   !< created by the ranks of a communicator (MPI-IO)
    integer :: rank = 0             !< this rank in it (0 on one process)
    type(MPI_Comm) :: comm          !< its communicator (parallel)
  end type h5_file_t

  !> Largest dataset rank accepted by the array writers.
  integer, parameter :: max_rank = 7

  interface
    !> H5Fget_obj_count (ssize_t H5Fget_obj_count(hid_t, unsigned)).
    function c_h5fget_obj_count(file_id, types) bind(c, name='H5Fget_obj_count') result(n)
      import :: c_int64_t, c_int, c_intptr_t
      integer(c_int64_t), value, intent(in) :: file_id   ! hid_t
      integer(c_int), value, intent(in) :: types
      integer(c_intptr_t) :: n
    end function c_h5fget_obj_count
  end interface

  !> glibc's struct statvfs on 64-bit Linux (every count an unsigned long;
  !> the spare words padded beyond its size).
  type, bind(c) :: c_statvfs_t
    integer(c_long) :: f_bsize, f_frsize, f_blocks, f_bfree, f_bavail, f_files, f_ffree, f_favail, f_fsid, &
                       f_flag, f_namemax
    integer(c_int) :: spare(16)
  end type c_statvfs_t

  interface
    !> statvfs(3): 0 on success.
    function c_statvfs(path, buf) bind(c, name='statvfs') result(rc)
      import :: c_char, c_int, c_statvfs_t
      character(kind=c_char), intent(in) :: path(*)
      type(c_statvfs_t), intent(out) :: buf
      integer(c_int) :: rc
    end function c_statvfs
    !> fopen(3), fileno(3), fclose(3), fallocate(2), unlink(2) and errno: the
    !> space reservation of a file of several ranks (`reserve_space`).
    function c_fopen(path, mode) bind(c, name='fopen') result(fp)
      import :: c_char, c_ptr
      character(kind=c_char), intent(in) :: path(*), mode(*)
      type(c_ptr) :: fp
    end function c_fopen
    function c_fileno(fp) bind(c, name='fileno') result(fd)
      import :: c_ptr, c_int
      type(c_ptr), value, intent(in) :: fp
      integer(c_int) :: fd
    end function c_fileno
    function c_fclose(fp) bind(c, name='fclose') result(rc)
      import :: c_ptr, c_int
      type(c_ptr), value, intent(in) :: fp
      integer(c_int) :: rc
    end function c_fclose
    function c_fallocate(fd, mode, offset, length) bind(c, name='fallocate') result(rc)
      import :: c_int, c_long
      integer(c_int), value, intent(in) :: fd, mode
      integer(c_long), value, intent(in) :: offset, length   ! off_t
      integer(c_int) :: rc
    end function c_fallocate
    function c_unlink(path) bind(c, name='unlink') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: rc
    end function c_unlink
    function c_errno_location() bind(c, name='__errno_location') result(p)
      import :: c_ptr
      type(c_ptr) :: p
    end function c_errno_location
  end interface

  !> Largest chunk of a checksummed or compressed dataset (bytes; module notes).
  integer(int64), parameter :: max_chunk_bytes = 2_int64**20

contains

  ! ------------------------------------------------------------------ library

  !> Initialises the HDF5 library (without its exit handler, see the module
  !> notes) and silences its error-stack printing. Safe to call more than
  !> once (h5open_f is; H5dont_atexit fails harmlessly once the library is
  !> up); the file openers call it themselves.
  subroutine hdf5_start(err)
    type(error_t), allocatable, intent(inout) :: err
    integer :: hdferr
    call h5dont_atexit_f(hdferr)
    call h5open_f(hdferr)
    if (hdferr /= 0) then
      call error_set(err, 'hdf5_start', 'h5open_f failed to initialise the HDF5 library')
      return
    end if
    call h5eset_auto_f(0, hdferr)
    if (hdferr /= 0) then
      call error_set(err, 'hdf5_start', 'h5eset_auto_f failed to silence HDF5 error printing')
      return
    end if
  end subroutine hdf5_start

  !> The HDF5 library's version, as text ('1.10.8').
  function hdf5_version() result(text)
    character(len=:), allocatable :: text
    integer :: major, minor, release, hdferr
    character(len=32) :: buf
    ! any HDF5 call starts the library: keep its exit handler off (hdf5_start)
    call h5dont_atexit_f(hdferr)
    call h5get_libversion_f(major, minor, release, hdferr)
    write(buf, '(i0,".",i0,".",i0)') major, minor, release
    text = trim(buf)
  end function hdf5_version

  !> Closes the HDF5 library (at the end of a run, or before a failed run
  !> halts), unless a file is still open: that is one whose close failed, on
  !> whose identifier HDF5 would crash, so the library is left as it is and
  !> `err` says so (the process is about to end; the OS closes the file).
  subroutine hdf5_stop(err)
    type(error_t), allocatable, intent(inout) :: err
    integer(c_intptr_t) :: nopen
    integer :: hdferr
    ! counting the identifiers does not touch the files they name (the C
    ! call: HDF5 1.10.8's h5fget_obj_count_f returns a wrong count)
    nopen = c_h5fget_obj_count(int(H5F_OBJ_ALL_F, c_int64_t), int(H5F_OBJ_FILE_F, c_int))
    if (nopen /= 0) then
      call error_set(err, 'hdf5_stop', 'an HDF5 file could not be closed (disk full?): the library is left open')
      return
    end if
    call h5close_f(hdferr)
    if (hdferr /= 0) call error_set(err, 'hdf5_stop', 'h5close_f failed to close the HDF5 library')
  end subroutine hdf5_stop

  ! -------------------------------------------------------------------- files

  !> Creates `path` (truncating any existing file) and opens it for writing.
  !> With `checksums` (default false) every dataset written to it carries a
  !> Fletcher-32 checksum and the file's metadata their own (module notes).
  !> With `comm` of more than one rank every rank of it calls this (and
  !> every later call on the file, with the same names and shapes: HDF5's
  !> parallel rules): the file is written through MPI-IO, every write
  !> collective; the whole-array writers then write rank 0's data (the other
  !> ranks' is not read) and `h5_write_part_*` each rank's part of a
  !> dataset.
  !>
  !> `need` (bytes, with comm): the file's size, about. HDF5's collective
  !> calls do not survive a failure on one rank (a dataset's space that one
  !> rank cannot allocate leaves the others waiting in HDF5 for ever), so the
  !> space of a file of several ranks is reserved before anything is written
  !> to it: rank 0 allocates `need` bytes (with a margin) to the new file at
  !> once (`reserve_space`), and a disk that others fill later cannot take
  !> them away. A file the disk has no room for is refused on every rank,
  !> and left behind by none: nothing collective is called on it again (it
  !> is not closed, `hdf5_stop`), and rank 0 removes it.
  subroutine h5_create(file, path, err, checksums, comm, need)
    type(h5_file_t), intent(inout) :: file
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: checksums
    type(MPI_Comm), intent(in), optional :: comm
    integer(int64), intent(in), optional :: need
    integer(hid_t) :: fapl
    integer :: hdferr, ierr, nranks
    call hdf5_start(err)
    if (allocated(err)) return
    if (file%id >= 0) then
      call error_set(err, 'h5_create', 'handle already open on '//q(file%path)//', cannot create '//q(path))
      return
    end if
    file%checksums = .false.
    if (present(checksums)) file%checksums = checksums
    file%parallel = .false.
    file%rank = 0
    nranks = 1
    if (present(comm)) then
      call MPI_Comm_size(comm, nranks)
      call MPI_Comm_rank(comm, file%rank)
    end if
    if (nranks > 1) then
      ! (every write is collective: parallel HDF5 1.10 writes filtered data,
      ! the checksums', only so)
      file%parallel = .true.
      file%comm = comm
      call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
      if (hdferr == 0) call h5pset_fapl_mpio_f(fapl, comm%MPI_VAL, MPI_INFO_NULL%MPI_VAL, hdferr)
      if (hdferr == 0 .and. file%checksums) &
        call h5pset_libver_bounds_f(fapl, H5F_LIBVER_LATEST_F, H5F_LIBVER_LATEST_F, hdferr)
      if (hdferr == 0) call h5fcreate_f(path, H5F_ACC_TRUNC_F, file%id, hdferr, access_prp=fapl)
      call h5pclose_f(fapl, ierr)
      if (present(need)) then
        if (hdferr /= 0) then
          call error_set(err, 'h5_create', 'cannot create HDF5 file '//q(path))
        else if (file%rank == 0) then
          call reserve_space(path, need, err)
        end if
        call agree_outcome(file, 'h5_create', 'cannot create HDF5 file '//q(path), err)
        if (allocated(err)) then
          ! abandoned (module notes): the identifier stays open
          file%id = -1_hid_t
          if (file%rank == 0) ierr = c_unlink(path//c_null_char)
          return
        end if
      end if
    else if (file%checksums) then
      ! the newest format: checksummed superblock, object headers and indexes
      call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
      if (hdferr /= 0) then
        call error_set(err, 'h5_create', 'cannot create a file access property list for '//q(path))
        return
      end if
      call h5pset_libver_bounds_f(fapl, H5F_LIBVER_LATEST_F, H5F_LIBVER_LATEST_F, hdferr)
      if (hdferr == 0) call h5fcreate_f(path, H5F_ACC_TRUNC_F, file%id, hdferr, access_prp=fapl)
      call h5pclose_f(fapl, ierr)
    else
      call h5fcreate_f(path, H5F_ACC_TRUNC_F, file%id, hdferr)
    end if
    if (hdferr /= 0) then
      file%id = -1_hid_t
      call error_set(err, 'h5_create', 'cannot create HDF5 file '//q(path))
      return
    end if
    file%path = path
  end subroutine h5_create

  !> Allocates `need` bytes and a margin (a tenth, and 64 KiB) to the file
  !> `path` without changing its size (fallocate, FALLOC_FL_KEEP_SIZE): its
  !> writes up to that size then cannot fail for want of space. An error if
  !> the file system has not that much room; where it cannot reserve space
  !> (no fallocate), an error if it has less free than that (statvfs; no
  !> check where that fails either).
  subroutine reserve_space(path, need, err)
    character(len=*), intent(in) :: path
    integer(int64), intent(in) :: need
    type(error_t), allocatable, intent(inout) :: err
    integer(c_int), parameter :: KEEP_SIZE = 1, ENOSPC = 28, EFBIG = 27
    type(c_statvfs_t) :: st
    type(c_ptr) :: fp
    integer(c_int), pointer :: errno
    integer(int64) :: free, bytes
    integer(c_int) :: rc, code
    integer :: k
    character(len=:), allocatable :: dir
    bytes = need + need/10 + 65536_int64
    fp = c_fopen(path//c_null_char, 'r+'//c_null_char)
    if (c_associated(fp)) then
      rc = c_fallocate(c_fileno(fp), KEEP_SIZE, 0_c_long, int(bytes, c_long))
      call c_f_pointer(c_errno_location(), errno)
      code = errno
      if (c_fclose(fp) /= 0 .and. rc == 0) code = 0
      if (rc == 0) return
      if (code == ENOSPC .or. code == EFBIG) then
        call error_set(err, 'h5_create', 'not enough space on the disk for '//q(path)//': '// &
                       itoa(bytes)//' bytes could not be reserved')
        return
      end if
    end if
    k = index(path, '/', back=.true.)
    dir = '.'
    if (k > 1) dir = path(1:k - 1)
    if (k == 1) dir = '/'
    if (c_statvfs(dir//c_null_char, st) /= 0) return
    free = int(st%f_bavail, int64)*int(st%f_frsize, int64)
    if (free < bytes) call error_set(err, 'h5_create', 'not enough space on the disk for '//q(path)//': '// &
                                     itoa(free)//' bytes free, about '//itoa(bytes)//' needed')
  end subroutine reserve_space

  !> Opens the existing HDF5 file `path` read-only.
  subroutine h5_open_read(file, path, err)
    type(h5_file_t), intent(inout) :: file
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer :: hdferr
    logical :: exists, is_hdf5
    call hdf5_start(err)
    if (allocated(err)) return
    if (file%id >= 0) then
      call error_set(err, 'h5_open_read', 'handle already open on '//q(file%path)//', cannot open '//q(path))
      return
    end if
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call error_set(err, 'h5_open_read', 'file '//q(path)//' does not exist')
      return
    end if
    call h5fis_hdf5_f(path, is_hdf5, hdferr)
    if (hdferr /= 0 .or. .not. is_hdf5) then
      call error_set(err, 'h5_open_read', 'file '//q(path)//' is not an HDF5 file')
      return
    end if
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file%id, hdferr)
    if (hdferr /= 0) then
      file%id = -1_hid_t
      call error_set(err, 'h5_open_read', 'cannot open HDF5 file '//q(path))
      return
    end if
    file%path = path
  end subroutine h5_open_read

  !> Flushes and closes `file`; does nothing if it is not open. After a
  !> failed close the identifier is dropped (HDF5 may have freed the file
  !> already; `hdf5_stop` will leave the library alone).
  subroutine h5_close(file, err)
    type(h5_file_t), intent(inout) :: file
    type(error_t), allocatable, intent(inout) :: err
    integer :: hdferr_flush, hdferr_close
    if (file%id < 0) return
    call h5fflush_f(file%id, H5F_SCOPE_GLOBAL_F, hdferr_flush)
    call h5fclose_f(file%id, hdferr_close)
    file%id = -1_hid_t
    if (hdferr_flush /= 0 .or. hdferr_close /= 0) then
      call error_set(err, 'h5_close', 'cannot flush/close HDF5 file '//q(fpath(file)))
    end if
    call agree_outcome(file, 'h5_close', 'cannot flush/close HDF5 file '//q(fpath(file)), err)
  end subroutine h5_close

  !> Creates group `name` (a path; missing parent groups are created too).
  subroutine h5_create_group(file, name, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_create_group'
    integer(hid_t) :: lcpl, gid
    integer :: hdferr
    if (.not. check_open(file, name, here, err)) return
    call link_plist(lcpl, hdferr)
    if (hdferr /= 0) then
      call error_set(err, here, 'cannot create link property list for '//where_in(file, name))
      return
    end if
    call h5gcreate_f(file%id, name, gid, hdferr, lcpl_id=lcpl)
    if (hdferr /= 0) then
      call error_set(err, here, 'cannot create group '//where_in(file, name))
    else
      call h5gclose_f(gid, hdferr)
      if (hdferr /= 0) call error_set(err, here, 'cannot close group '//where_in(file, name))
    end if
    call h5pclose_f(lcpl, hdferr)
  end subroutine h5_create_group

  !> True if the link `name` (a path) exists in the open `file`.
  function h5_exists(file, name) result(exists)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    logical :: exists
    integer :: pos, start, hdferr
    logical :: link
    exists = .false.
    if (file%id < 0) return
    start = 1
    do while (start <= len(name))
      if (name(start:start) /= '/') exit
      start = start + 1
    end do
    if (start > len(name)) then
      exists = .true.
      return
    end if
    ! Check each parent prefix so a missing intermediate group is no error.
    do pos = start + 1, len(name) - 1
      if (name(pos:pos) /= '/') cycle
      call h5lexists_f(file%id, name(1:pos - 1), link, hdferr)
      if (hdferr /= 0 .or. .not. link) return
    end do
    call h5lexists_f(file%id, name, link, hdferr)
    exists = hdferr == 0 .and. link
  end function h5_exists

  ! ------------------------------------------------------------------ writers

  !> Writes a double dataset of shape `dims` (Fortran order, rank 1..7) from
  !> the contiguous buffer `data`, which holds product(dims) values; with
  !> `single` stored as float32, with `deflate` (1..9; 0: off) compressed
  !> (module notes).
  subroutine h5_write_real(file, name, data, dims, err, single, deflate)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    real(wp), intent(in), target :: data(*)
    integer, intent(in) :: dims(:)
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: single
    integer, intent(in), optional :: deflate
    real(real32), allocatable, target :: buf(:)
    type(c_ptr) :: ptr
    integer(int64) :: n
    n = 0
    ptr = c_null_ptr
    if (size(dims) > 0) then
      if (all(dims > 0)) then
        ptr = c_loc(data(1))
        n = product(int(dims, int64))
      end if
    end if
    if (.not. opt_true(single)) then
      call write_array(file, name, ptr, dims, h5kind_to_type(wp, H5_REAL_KIND), 'h5_write_real', err, deflate)
      return
    end if
    call single_copy(file, data, n, buf, ptr, 'h5_write_real', name, err)
    if (allocated(err)) return
    call write_array(file, name, ptr, dims, h5kind_to_type(real32, H5_REAL_KIND), 'h5_write_real', err, deflate)
  end subroutine h5_write_real

  !> Writes a default-integer dataset of shape `dims` (Fortran order, rank
  !> 1..7) from the contiguous buffer `data`, which holds product(dims) values;
  !> with `deflate` (1..9; 0: off) compressed.
  subroutine h5_write_int(file, name, data, dims, err, deflate)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, intent(in), target :: data(*)
    integer, intent(in) :: dims(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: deflate
    type(c_ptr) :: ptr
    ptr = c_null_ptr
    if (size(dims) > 0) then
      if (all(dims > 0)) ptr = c_loc(data(1))
    end if
    call write_array(file, name, ptr, dims, h5kind_to_type(kind(0), H5_INTEGER_KIND), 'h5_write_int', err, deflate)
  end subroutine h5_write_int

  !> This rank's part (a box of shape `count` at the 0-based `start`) of the
  !> double dataset `name` of shape `dims`, from the contiguous buffer `data`
  !> (product(count) values), written by all ranks of a parallel file
  !> together (`h5_create` with `comm`; on one process the whole dataset).
  !> With `grid` the dataset's last dimension is a grid of that shape,
  !> flattened, and the box is given in the grid's dimensions (`write_part`).
  !> With `runs` (2, nrun: 0-based start and length, increasing) the part is
  !> those runs of the last dimension, the leading ones whole (start 0,
  !> count the leading dimensions and the runs' total): a rank's particles
  !> at their places among all ranks'.
  !> `single` and `deflate` as for `h5_write_real` (the same on every rank).
  subroutine h5_write_part_real(file, name, data, dims, start, count, err, grid, single, deflate, runs)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    real(wp), intent(in), target :: data(*)
    integer, intent(in) :: dims(:), start(:), count(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: grid(3)
    logical, intent(in), optional :: single
    integer, intent(in), optional :: deflate
    integer, intent(in), optional :: runs(:, :)
    real(real32), allocatable, target :: buf(:)
    type(c_ptr) :: ptr
    integer(int64) :: n
    n = 0
    ptr = c_null_ptr
    if (size(count) > 0) then
      if (all(count > 0)) then
        ptr = c_loc(data(1))
        n = product(int(count, int64))
      end if
    end if
    if (.not. opt_true(single)) then
      call write_part(file, name, ptr, dims, start, count, h5kind_to_type(wp, H5_REAL_KIND), 'h5_write_part_real', &
                      err, grid, deflate, runs)
      return
    end if
    call single_copy(file, data, n, buf, ptr, 'h5_write_part_real', name, err)
    if (allocated(err)) return
    call write_part(file, name, ptr, dims, start, count, h5kind_to_type(real32, H5_REAL_KIND), 'h5_write_part_real', &
                    err, grid, deflate, runs)
  end subroutine h5_write_part_real

  !> `h5_write_part_real` for a default-integer dataset.
  subroutine h5_write_part_int(file, name, data, dims, start, count, err, grid, deflate, runs)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, intent(in), target :: data(*)
    integer, intent(in) :: dims(:), start(:), count(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: grid(3)
    integer, intent(in), optional :: deflate
    integer, intent(in), optional :: runs(:, :)
    type(c_ptr) :: ptr
    ptr = c_null_ptr
    if (size(count) > 0) then
      if (all(count > 0)) ptr = c_loc(data(1))
    end if
    call write_part(file, name, ptr, dims, start, count, h5kind_to_type(kind(0), H5_INTEGER_KIND), &
                    'h5_write_part_int', err, grid, deflate, runs)
  end subroutine h5_write_part_int

  !> The float32 copy `buf` of the n doubles of `data` (`to_single`), `ptr`
  !> its address (null for none); out of memory on any rank of the file: an
  !> error on all of them (before any collective call on the dataset).
  subroutine single_copy(file, data, n, buf, ptr, here, name, err)
    type(h5_file_t), intent(in) :: file
    real(wp), intent(in) :: data(*)
    integer(int64), intent(in) :: n
    real(real32), allocatable, target, intent(out) :: buf(:)
    type(c_ptr), intent(out) :: ptr
    character(len=*), intent(in) :: here, name
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    ptr = c_null_ptr
    allocate(buf(n), stat=stat)
    if (stat /= 0) call error_set(err, here, error_no_memory('the float32 copy of '//q(name)//' ('// &
                                  itoa(int(n))//' values)'))
    call agree_outcome(file, here, 'cannot write '//where_in(file, name), err)
    if (allocated(err) .or. n == 0) return
    buf = to_single(data(1:n))
    ptr = c_loc(buf(1))
  end subroutine single_copy

  !> x as float32, rounded to nearest (ties to even, the hardware's mode,
  !> as numpy's float32()); beyond the float32 range (from FLT_MAX plus half
  !> its last place on, where rounding reaches infinity) +-infinity and a
  !> NaN a quiet NaN, set without the conversion that would trap under
  !> -ffpe-trap=overflow,invalid.
  elemental function to_single(x) result(s)
    real(wp), intent(in) :: x
    real(real32) :: s
    real(wp), parameter :: beyond = real(huge(1.0_real32), wp) + 2.0_wp**103
    if (ieee_is_nan(x)) then
      s = ieee_value(s, ieee_quiet_nan)
    else if (x >= beyond) then
      s = ieee_value(s, ieee_positive_inf)
    else if (x <= -beyond) then
      s = ieee_value(s, ieee_negative_inf)
    else
      s = real(x, real32)
    end if
  end function to_single

  !> An optional flag's value (absent: false).
  pure logical function opt_true(flag)
    logical, intent(in), optional :: flag
    opt_true = .false.
    if (present(flag)) opt_true = flag
  end function opt_true

  !> Writes a scalar double dataset.
  subroutine h5_write_scalar_real(file, name, value, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: value
    type(error_t), allocatable, intent(inout) :: err
    real(wp), target :: buf
    type(c_ptr) :: ptr
    buf = value
    ptr = c_loc(buf)
    call write_scalar(file, name, ptr, h5kind_to_type(wp, H5_REAL_KIND), 'h5_write_scalar_real', err)
  end subroutine h5_write_scalar_real

  !> Writes a scalar default-integer dataset.
  subroutine h5_write_scalar_int(file, name, value, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, intent(in) :: value
    type(error_t), allocatable, intent(inout) :: err
    integer, target :: buf
    type(c_ptr) :: ptr
    buf = value
    ptr = c_loc(buf)
    call write_scalar(file, name, ptr, h5kind_to_type(kind(0), H5_INTEGER_KIND), &
         'h5_write_scalar_int', err)
  end subroutine h5_write_scalar_int

  !> Writes `text` (any length, newlines allowed, no NUL characters) as a
  !> scalar fixed-length, null-padded string dataset.
  subroutine h5_write_string(file, name, text, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: text
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_write_string'
    character(len=:), allocatable, target :: buf
    integer(hid_t) :: tid
    integer :: hdferr
    type(c_ptr) :: ptr
    ! HDF5 strings need at least one byte: the empty string is stored as NUL.
    ! allocation on assignment (an explicit allocate trips gfortran's
    ! maybe-uninitialized warning on deferred-length strings)
    if (len(text) == 0) then
      buf = c_null_char
    else
      buf = text
    end if
    call string_type(int(len(buf), size_t), tid, hdferr)
    if (hdferr /= 0) then
      call error_set(err, here, 'cannot create string type for '//where_in(file, name))
      return
    end if
    ptr = c_loc(buf)
    call write_scalar(file, name, ptr, tid, here, err)
    call h5tclose_f(tid, hdferr)
  end subroutine h5_write_string

  ! ------------------------------------------------------------------ readers

  !> Returns the shape of dataset `name` in Fortran order (size 0 for scalars).
  subroutine h5_read_dims(file, name, dims, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, allocatable, intent(out) :: dims(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_read_dims'
    integer(hid_t) :: did, sid
    integer(hsize_t) :: hdims(max_rank), hmax(max_rank)
    integer :: hdferr, rank, stat
    did = -1_hid_t
    sid = -1_hid_t
    body: block
      if (.not. open_dataset(file, name, here, did, err)) exit body
      call h5dget_space_f(did, sid, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot get dataspace of '//where_in(file, name))
        exit body
      end if
      call h5sget_simple_extent_ndims_f(sid, rank, hdferr)
      if (hdferr /= 0 .or. rank < 0 .or. rank > max_rank) then
        call error_set(err, here, 'unsupported rank of '//where_in(file, name))
        exit body
      end if
      allocate(dims(rank), stat=stat)
      if (stat /= 0) then
        call error_set(err, here, error_no_memory('dims for '//where_in(file, name)))
        exit body
      end if
      if (rank == 0) exit body
      call h5sget_simple_extent_dims_f(sid, hdims(1:rank), hmax(1:rank), hdferr)
      if (hdferr < 0) then
        call error_set(err, here, 'cannot get dimensions of '//where_in(file, name))
        exit body
      end if
      dims = int(hdims(1:rank))
    end block body
    call release(did, sid, -1_hid_t)
  end subroutine h5_read_dims

  !> Reads a floating-point dataset of any shape, flattened in Fortran order;
  !> with grid, start and count only a box of it, as `h5_write_part_real`
  !> writes one; with start and count alone the box start(d) ..
  !> start(d) + count(d) - 1 (0-based) of each of its dimensions (the caller
  !> has checked that it lies in the dataset); with runs the runs of its last
  !> dimension runs(:, r) = (0-based start, length), increasing and within
  !> it, the leading dimensions whole (as `h5_write_part_real` writes them).
  subroutine h5_read_real(file, name, data, err, grid, start, count, runs)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    real(wp), allocatable, target, intent(out) :: data(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: grid(3), start(:), count(:), runs(:, :)
    character(len=*), parameter :: here = 'h5_read_real'
    integer(hid_t) :: did, sid
    integer(hsize_t) :: n
    integer :: hdferr, stat
    type(c_ptr) :: ptr
    did = -1_hid_t
    sid = -1_hid_t
    body: block
      if (.not. open_checked(file, name, H5T_FLOAT_F, 'floating-point', here, did, sid, n, err)) exit body
      if (present(count)) n = product(int(count, hsize_t))
      if (present(runs)) call runs_size(sid, runs, n)
      allocate(data(n), stat=stat)
      if (stat /= 0) then
        call error_set(err, here, error_no_memory('memory for '//where_in(file, name)))
        exit body
      end if
      if (n == 0) exit body
      ptr = c_loc(data(1))
      call read_selected(did, sid, h5kind_to_type(wp, H5_REAL_KIND), ptr, n, hdferr, grid, start, count, runs)
      if (hdferr /= 0) call error_set(err, here, damaged(file, name))
    end block body
    call release(did, sid, -1_hid_t)
  end subroutine h5_read_real

  !> Reads an integer dataset of any shape, flattened in Fortran order (or a
  !> box or runs of it, as `h5_read_real`).
  subroutine h5_read_int(file, name, data, err, grid, start, count, runs)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, allocatable, target, intent(out) :: data(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: grid(3), start(:), count(:), runs(:, :)
    character(len=*), parameter :: here = 'h5_read_int'
    integer(hid_t) :: did, sid
    integer(hsize_t) :: n
    integer :: hdferr, stat
    type(c_ptr) :: ptr
    did = -1_hid_t
    sid = -1_hid_t
    body: block
      if (.not. open_checked(file, name, H5T_INTEGER_F, 'integer', here, did, sid, n, err)) exit body
      if (present(count)) n = product(int(count, hsize_t))
      if (present(runs)) call runs_size(sid, runs, n)
      allocate(data(n), stat=stat)
      if (stat /= 0) then
        call error_set(err, here, error_no_memory('memory for '//where_in(file, name)))
        exit body
      end if
      if (n == 0) exit body
      ptr = c_loc(data(1))
      call read_selected(did, sid, h5kind_to_type(kind(0), H5_INTEGER_KIND), ptr, n, hdferr, grid, start, count, runs)
      if (hdferr /= 0) call error_set(err, here, damaged(file, name))
    end block body
    call release(did, sid, -1_hid_t)
  end subroutine h5_read_int

  !> Reads a one-element floating-point dataset.
  subroutine h5_read_scalar_real(file, name, value, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    real(wp), intent(out) :: value
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_read_scalar_real'
    integer(hid_t) :: did, sid
    integer(hsize_t) :: n
    integer :: hdferr
    real(wp), target :: buf
    type(c_ptr) :: ptr
    value = 0.0_wp
    did = -1_hid_t
    sid = -1_hid_t
    body: block
      if (.not. open_checked(file, name, H5T_FLOAT_F, 'floating-point', here, did, sid, n, err)) exit body
      if (n /= 1) then
        call error_set(err, here, 'expected one value in '//where_in(file, name))
        exit body
      end if
      ptr = c_loc(buf)
      call h5dread_f(did, h5kind_to_type(wp, H5_REAL_KIND), ptr, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, damaged(file, name))
        exit body
      end if
      value = buf
    end block body
    call release(did, sid, -1_hid_t)
  end subroutine h5_read_scalar_real

  !> Reads a one-element integer dataset.
  subroutine h5_read_scalar_int(file, name, value, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, intent(out) :: value
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_read_scalar_int'
    integer(hid_t) :: did, sid
    integer(hsize_t) :: n
    integer :: hdferr
    integer, target :: buf
    type(c_ptr) :: ptr
    value = 0
    did = -1_hid_t
    sid = -1_hid_t
    body: block
      if (.not. open_checked(file, name, H5T_INTEGER_F, 'integer', here, did, sid, n, err)) exit body
      if (n /= 1) then
        call error_set(err, here, 'expected one value in '//where_in(file, name))
        exit body
      end if
      ptr = c_loc(buf)
      call h5dread_f(did, h5kind_to_type(kind(0), H5_INTEGER_KIND), ptr, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, damaged(file, name))
        exit body
      end if
      value = buf
    end block body
    call release(did, sid, -1_hid_t)
  end subroutine h5_read_scalar_int

  !> Reads a scalar fixed-length string dataset; the text ends at the first NUL.
  subroutine h5_read_string(file, name, text, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: text
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_read_string'
    integer(hid_t) :: did, sid, ftid, mtid
    integer(hsize_t) :: n
    integer(size_t) :: nchar
    integer :: hdferr, nul
    logical :: is_var
    character(len=:), allocatable, target :: buf
    type(c_ptr) :: ptr
    did = -1_hid_t
    sid = -1_hid_t
    ftid = -1_hid_t
    mtid = -1_hid_t
    body: block
      if (.not. open_checked(file, name, H5T_STRING_F, 'string', here, did, sid, n, err)) exit body
      if (n /= 1) then
        call error_set(err, here, 'expected one string in '//where_in(file, name))
        exit body
      end if
      call h5dget_type_f(did, ftid, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot get type of '//where_in(file, name))
        exit body
      end if
      call h5tis_variable_str_f(ftid, is_var, hdferr)
      if (hdferr /= 0 .or. is_var) then
        call error_set(err, here, 'variable-length strings unsupported in '//where_in(file, name))
        exit body
      end if
      call h5tget_size_f(ftid, nchar, hdferr)
      if (hdferr /= 0 .or. nchar < 1) then
        call error_set(err, here, 'cannot get string size of '//where_in(file, name))
        exit body
      end if
      call string_type(nchar, mtid, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot create string type for '//where_in(file, name))
        exit body
      end if
      buf = repeat(c_null_char, int(nchar))
      ptr = c_loc(buf)
      call h5dread_f(did, mtid, ptr, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, damaged(file, name))
        exit body
      end if
      nul = index(buf, c_null_char)
      if (nul > 0) then
        text = buf(1:nul - 1)
      else
        call move_alloc(buf, text)
      end if
    end block body
    if (mtid >= 0) call h5tclose_f(mtid, hdferr)
    call release(did, sid, ftid)
  end subroutine h5_read_string

  ! ------------------------------------------------------------------ helpers

  !> Writes a whole dataset from ptr; in a file of several ranks rank 0's
  !> data (the others select nothing).
  subroutine write_root(file, did, tid, sid, ptr, hdferr)
    type(h5_file_t), intent(in) :: file
    integer(hid_t), intent(in) :: did, tid, sid
    type(c_ptr), intent(inout) :: ptr
    integer, intent(out) :: hdferr
    integer(hid_t) :: xfer
    integer :: ierr
    if (.not. file%parallel) then
      call h5dwrite_f(did, tid, ptr, hdferr)
      return
    end if
    call collective_plist(xfer, hdferr)
    if (hdferr /= 0) return
    if (file%rank /= 0) then
      call h5sselect_none_f(sid, hdferr)
      if (hdferr == 0) call h5dwrite_f(did, tid, ptr, hdferr, mem_space_id=sid, file_space_id=sid, xfer_prp=xfer)
    else
      call h5dwrite_f(did, tid, ptr, hdferr, xfer_prp=xfer)
    end if
    call h5pclose_f(xfer, ierr)
  end subroutine write_root

  !> A data transfer property list for collective MPI-IO.
  subroutine collective_plist(xfer, hdferr)
    integer(hid_t), intent(out) :: xfer
    integer, intent(out) :: hdferr
    integer :: ierr
    call h5pcreate_f(H5P_DATASET_XFER_F, xfer, hdferr)
    if (hdferr /= 0) then
      xfer = -1_hid_t
      return
    end if
    call h5pset_dxpl_mpio_f(xfer, H5FD_MPIO_COLLECTIVE_F, hdferr)
    if (hdferr /= 0) then
      call h5pclose_f(xfer, ierr)
      xfer = -1_hid_t
    end if
  end subroutine collective_plist

  !> Creates the dataset `name` of shape `dims` (Fortran order) in a file of
  !> several ranks and writes this rank's part of it, the box of shape
  !> `count` at `start` (0-based, Fortran order), from the contiguous buffer
  !> ptr (product(count) values), all ranks together (collective MPI-IO).
  !> With `grid`, the last dimension of the dataset is a grid of shape
  !> grid(1:3) flattened (i fastest), and start and count give the box in
  !> the leading dimensions and then in the grid's three (size(dims) + 2
  !> values). In a file of one process the part must be the whole dataset.
  subroutine write_part(file, name, ptr, dims, start, count, tid, here, err, grid, deflate, runs)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    type(c_ptr), intent(inout) :: ptr
    integer, intent(in) :: dims(:), start(:), count(:)
    integer(hid_t), intent(in) :: tid
    character(len=*), intent(in) :: here
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: grid(3)
    integer, intent(in), optional :: deflate
    integer, intent(in), optional :: runs(:, :)
    integer(hid_t) :: did, sid, msid, lcpl, xfer, dcpl
    integer, allocatable :: whole(:)
    integer :: hdferr, rank, nlead
    rank = size(dims)
    nlead = rank - 1
    ! the part's box in the dataset's own dimensions, or in the grid's
    if (present(grid)) then
      whole = [dims(1:nlead), grid]
    else
      whole = dims
    end if
    if (rank < 1 .or. rank > max_rank .or. size(start) /= size(whole) .or. size(count) /= size(whole)) then
      call error_set(err, here, 'rank must be 1..7, the same for the part, for '//where_in(file, name))
    else if (present(grid)) then
      if (dims(rank) /= product(grid)) &
        call error_set(err, here, 'the grid does not match the last dimension of '//where_in(file, name))
    end if
    if (.not. allocated(err)) then
      if (any(start < 0) .or. any(count < 0) .or. any(start + count > whole)) &
        call error_set(err, here, 'the part lies outside '//where_in(file, name))
    end if
    if (.not. allocated(err) .and. present(runs)) then
      if (present(grid) .or. size(runs, 1) /= 2 .or. any(start /= 0) .or. any(count(1:nlead) /= dims(1:nlead))) then
        call error_set(err, here, 'runs select whole leading dimensions of '//where_in(file, name))
      else if (sum(runs(2, :)) /= count(rank)) then
        call error_set(err, here, 'the runs do not hold the part''s values of '//where_in(file, name))
      else if (size(runs, 2) > 0) then
        if (any(runs(1, :) < 0) .or. any(runs(2, :) < 1) .or. any(runs(1, :) + runs(2, :) > dims(rank)) .or. &
            any(runs(1, 2:) < runs(1, :size(runs, 2) - 1) + runs(2, :size(runs, 2) - 1))) &
          call error_set(err, here, 'the runs are not increasing and within '//where_in(file, name))
      end if
    end if
    if (allocated(err)) then
      call agree_outcome(file, here, 'cannot write '//where_in(file, name), err)
      return
    end if
    if (.not. file%parallel) then
      if (any(count /= whole)) then
        call error_set(err, here, 'a part of '//where_in(file, name)//' in a file of one process')
        return
      end if
      call write_array(file, name, ptr, dims, tid, here, err, deflate)
      return
    end if
    did = -1_hid_t
    sid = -1_hid_t
    msid = -1_hid_t
    lcpl = -1_hid_t
    xfer = -1_hid_t
    dcpl = -1_hid_t
    body: block
      if (.not. check_open(file, name, here, err)) exit body
      call h5screate_simple_f(rank, int(dims, hsize_t), sid, hdferr)
      if (hdferr == 0) call h5screate_simple_f(1, [int(product(count), hsize_t)], msid, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot create dataspace for '//where_in(file, name))
        exit body
      end if
      if ((file%checksums .or. level(deflate) > 0) .and. product(dims) > 0) then
        call chunked_plist(int(dims, hsize_t), tid, file%checksums, level(deflate), dcpl, hdferr)
        if (hdferr /= 0) then
          call error_set(err, here, 'cannot set up the checksum or compression of '//where_in(file, name))
          exit body
        end if
      end if
      call create_dataset(file, name, tid, sid, lcpl, did, here, err, dcpl)
      if (allocated(err) .or. product(dims) == 0) exit body
      if (product(count) == 0) then
        call h5sselect_none_f(sid, hdferr)
        if (hdferr == 0) call h5sselect_none_f(msid, hdferr)
      else if (present(grid)) then
        call select_box(sid, rank, grid, start, count, hdferr)
      else if (present(runs)) then
        call select_runs(sid, dims, runs, hdferr)
      else
        call h5sselect_hyperslab_f(sid, H5S_SELECT_SET_F, int(start, hsize_t), int(count, hsize_t), hdferr)
      end if
      if (hdferr == 0) call collective_plist(xfer, hdferr)
      if (hdferr == 0) call h5dwrite_f(did, tid, ptr, hdferr, mem_space_id=msid, file_space_id=sid, xfer_prp=xfer)
      if (hdferr /= 0) call error_set(err, here, 'cannot write this rank''s part of '//where_in(file, name))
    end block body
    call release(did, sid, -1_hid_t)
    if (msid >= 0) call h5sclose_f(msid, hdferr)
    if (lcpl >= 0) call h5pclose_f(lcpl, hdferr)
    if (xfer >= 0) call h5pclose_f(xfer, hdferr)
    if (dcpl >= 0) call h5pclose_f(dcpl, hdferr)
    call agree_outcome(file, here, 'cannot write '//where_in(file, name), err)
  end subroutine write_part

  !> In a file of several ranks: an error on any rank an error on all (a
  !> rank's MPI-IO write can fail alone, a full disk under its aggregator;
  !> every rank must then leave the file's collective calls together),
  !> with `msg` on the ranks where nothing failed. A no-op on one process.
  subroutine agree_outcome(file, here, msg, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: here, msg
    type(error_t), allocatable, intent(inout) :: err
    logical :: mine, some
    if (.not. file%parallel) return
    mine = allocated(err)
    call MPI_Allreduce(mine, some, 1, MPI_LOGICAL, MPI_LOR, file%comm)
    if (some .and. .not. mine) call error_set(err, here, msg//' (failed on another rank)')
  end subroutine agree_outcome

  !> Selects in sid (a dataset of `rank` dimensions whose last is a grid of
  !> shape grid flattened, i fastest) the box at start of shape count, given
  !> in the leading dimensions and then the grid's three (rank + 2 values):
  !> one hyperslab per grid plane of the box, its rows each a run of i with
  !> the leading dimensions whole. The selection's order (HDF5's, by offset)
  !> is a buffer's filled with the leading dimensions fastest, then i, j, k.
  subroutine select_box(sid, rank, grid, start, count, hdferr)
    integer(hid_t), intent(in) :: sid
    integer, intent(in) :: rank, grid(3), start(:), count(:)
    integer, intent(out) :: hdferr
    integer(hsize_t) :: hs(rank), hc(rank), hst(rank), hb(rank)
    integer :: k
    hs(1:rank - 1) = int(start(1:rank - 1), hsize_t)
    hb(1:rank - 1) = int(count(1:rank - 1), hsize_t)
    hc(1:rank - 1) = 1_hsize_t
    hst(1:rank - 1) = max(hb(1:rank - 1), 1_hsize_t)
    hc(rank) = int(count(rank + 1), hsize_t)
    hb(rank) = int(count(rank), hsize_t)
    hst(rank) = int(grid(1), hsize_t)
    hdferr = 0
    do k = start(rank + 2), start(rank + 2) + count(rank + 2) - 1
      hs(rank) = int(start(rank), hsize_t) + int(grid(1), hsize_t)*(int(start(rank + 1), hsize_t) + &
                 int(grid(2), hsize_t)*int(k, hsize_t))
      call h5sselect_hyperslab_f(sid, merge(H5S_SELECT_SET_F, H5S_SELECT_OR_F, k == start(rank + 2)), &
                                 hs, hc, hdferr, hst, hb)
      if (hdferr /= 0) return
    end do
  end subroutine select_box

  !> Selects in sid (a dataset of shape dims) the runs of its last
  !> dimension runs(:, r) = (0-based start, length), increasing, the
  !> leading dimensions whole: a buffer's order, leading dimensions fastest.
  subroutine select_runs(sid, dims, runs, hdferr)
    integer(hid_t), intent(in) :: sid
    integer, intent(in) :: dims(:), runs(:, :)
    integer, intent(out) :: hdferr
    integer(hsize_t) :: hs(size(dims)), hc(size(dims))
    integer :: r, rank
    rank = size(dims)
    hs = 0_hsize_t
    hc(1:rank - 1) = int(dims(1:rank - 1), hsize_t)
    hdferr = 0
    do r = 1, size(runs, 2)
      hs(rank) = int(runs(1, r), hsize_t)
      hc(rank) = int(runs(2, r), hsize_t)
      call h5sselect_hyperslab_f(sid, merge(H5S_SELECT_SET_F, H5S_SELECT_OR_F, r == 1), hs, hc, hdferr)
      if (hdferr /= 0) return
    end do
  end subroutine select_runs

  !> n: the values the runs of the last dimension of dataspace sid select,
  !> its leading dimensions whole (`select_runs`).
  subroutine runs_size(sid, runs, n)
    integer(hid_t), intent(in) :: sid
    integer, intent(in) :: runs(:, :)
    integer(hsize_t), intent(out) :: n
    integer(hsize_t) :: hdims(max_rank), hmax(max_rank)
    integer :: rank, hdferr
    call h5sget_simple_extent_ndims_f(sid, rank, hdferr)
    call h5sget_simple_extent_dims_f(sid, hdims(1:rank), hmax(1:rank), hdferr)
    n = product(hdims(1:rank - 1))*sum(int(runs(2, :), hsize_t))
  end subroutine runs_size

  !> Reads a dataset into ptr: the whole of it, or with grid the box at
  !> start of shape count (n values; `select_box`, which must lie in it), or
  !> with count alone the hyperslab at start of shape count, or the runs of
  !> its last dimension (`select_runs`).
  subroutine read_selected(did, sid, tid, ptr, n, hdferr, grid, start, count, runs)
    integer(hid_t), intent(in) :: did, sid, tid
    type(c_ptr), intent(inout) :: ptr
    integer(hsize_t), intent(in) :: n
    integer, intent(out) :: hdferr
    integer, intent(in), optional :: grid(3), start(:), count(:), runs(:, :)
    integer(hid_t) :: msid
    integer(hsize_t) :: hdims(max_rank), hmax(max_rank)
    integer :: rank, ierr
    if (.not. (present(count) .or. present(runs))) then
      call h5dread_f(did, tid, ptr, hdferr)
      return
    end if
    if (present(runs)) then
      call h5sget_simple_extent_ndims_f(sid, rank, hdferr)
      if (hdferr == 0) call h5sget_simple_extent_dims_f(sid, hdims(1:rank), hmax(1:rank), hdferr)
      if (hdferr < 0) return
      call select_runs(sid, int(hdims(1:rank)), runs, hdferr)
    else if (present(grid)) then
      call h5sget_simple_extent_ndims_f(sid, rank, hdferr)
      if (hdferr /= 0) return
      call select_box(sid, rank, grid, start, count, hdferr)
    else
      call h5sselect_hyperslab_f(sid, H5S_SELECT_SET_F, int(start, hsize_t), int(count, hsize_t), hdferr)
    end if
    if (hdferr /= 0) return
    call h5screate_simple_f(1, [n], msid, hdferr)
    if (hdferr /= 0) return
    call h5dread_f(did, tid, ptr, hdferr, mem_space_id=msid, file_space_id=sid)
    call h5sclose_f(msid, ierr)
  end subroutine read_selected

  !> Creates and writes a simple-dataspace dataset from a buffer address.
  subroutine write_array(file, name, ptr, dims, tid, here, err, deflate)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    type(c_ptr), intent(inout) :: ptr
    integer, intent(in) :: dims(:)
    integer(hid_t), intent(in) :: tid
    character(len=*), intent(in) :: here
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: deflate
    integer(hid_t) :: did, sid, lcpl, dcpl
    integer(hsize_t) :: hdims(max_rank)
    integer :: hdferr, rank
    did = -1_hid_t
    sid = -1_hid_t
    lcpl = -1_hid_t
    dcpl = -1_hid_t
    rank = size(dims)
    body: block
      if (.not. check_open(file, name, here, err)) exit body
      if (rank < 1 .or. rank > max_rank) then
        call error_set(err, here, 'rank must be 1..7 for '//where_in(file, name))
        exit body
      end if
      if (any(dims < 0)) then
        call error_set(err, here, 'negative dimension for '//where_in(file, name))
        exit body
      end if
      hdims(1:rank) = int(dims, hsize_t)
      call h5screate_simple_f(rank, hdims(1:rank), sid, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot create dataspace for '//where_in(file, name))
        exit body
      end if
      ! a zero-size array has no data to checksum or compress: contiguous (module notes)
      if ((file%checksums .or. level(deflate) > 0) .and. product(hdims(1:rank)) > 0) then
        call chunked_plist(hdims(1:rank), tid, file%checksums, level(deflate), dcpl, hdferr)
        if (hdferr /= 0) then
          call error_set(err, here, 'cannot set up the checksum or compression of '//where_in(file, name))
          exit body
        end if
      end if
      call create_dataset(file, name, tid, sid, lcpl, did, here, err, dcpl)
      if (allocated(err)) exit body
      if (product(hdims(1:rank)) == 0) exit body
      call write_root(file, did, tid, sid, ptr, hdferr)
      if (hdferr /= 0) call error_set(err, here, 'cannot write '//where_in(file, name))
    end block body
    call release(did, sid, -1_hid_t)
    if (lcpl >= 0) call h5pclose_f(lcpl, hdferr)
    if (dcpl >= 0) call h5pclose_f(dcpl, hdferr)
    call agree_outcome(file, here, 'cannot write '//where_in(file, name), err)
  end subroutine write_array

  !> Creates and writes a scalar-dataspace dataset from a buffer address; in
  !> a checksummed file, a one-element chunked array with its checksum.
  subroutine write_scalar(file, name, ptr, tid, here, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    type(c_ptr), intent(inout) :: ptr
    integer(hid_t), intent(in) :: tid
    character(len=*), intent(in) :: here
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: did, sid, lcpl, dcpl
    integer(hsize_t), parameter :: one(1) = 1_hsize_t
    integer :: hdferr
    did = -1_hid_t
    sid = -1_hid_t
    lcpl = -1_hid_t
    dcpl = -1_hid_t
    body: block
      if (.not. check_open(file, name, here, err)) exit body
      if (file%checksums) then
        call h5screate_simple_f(1, one, sid, hdferr)
      else
        call h5screate_f(H5S_SCALAR_F, sid, hdferr)
      end if
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot create dataspace for '//where_in(file, name))
        exit body
      end if
      if (file%checksums) then
        call chunked_plist(one, tid, .true., 0, dcpl, hdferr)
        if (hdferr /= 0) then
          call error_set(err, here, 'cannot set up the checksum of '//where_in(file, name))
          exit body
        end if
      end if
      call create_dataset(file, name, tid, sid, lcpl, did, here, err, dcpl)
      if (allocated(err)) exit body
      call write_root(file, did, tid, sid, ptr, hdferr)
      if (hdferr /= 0) call error_set(err, here, 'cannot write '//where_in(file, name))
    end block body
    call release(did, sid, -1_hid_t)
    if (lcpl >= 0) call h5pclose_f(lcpl, hdferr)
    if (dcpl >= 0) call h5pclose_f(dcpl, hdferr)
    call agree_outcome(file, here, 'cannot write '//where_in(file, name), err)
  end subroutine write_scalar

  !> A deflate level: `deflate` if present, else 0 (off).
  pure integer function level(deflate)
    integer, intent(in), optional :: deflate
    level = 0
    if (present(deflate)) level = deflate
  end function level

  !> Dataset creation property list of a chunked dataset of shape `hdims`
  !> (Fortran order, no zero), its chunks cut along the last dimension to at
  !> most max_chunk_bytes: with `checksum` Fletcher-32 over each chunk, with
  !> `deflate` (1..9) byte shuffle and deflate at that level first.
  subroutine chunked_plist(hdims, tid, checksum, deflate, dcpl, hdferr)
    integer(hsize_t), intent(in) :: hdims(:)
    integer(hid_t), intent(in) :: tid
    logical, intent(in) :: checksum
    integer, intent(in) :: deflate
    integer(hid_t), intent(out) :: dcpl
    integer, intent(out) :: hdferr
    integer(hsize_t) :: chunk(size(hdims))
    integer(size_t) :: bytes
    integer(int64) :: slab
    integer :: rank, ierr
    rank = size(hdims)
    call h5tget_size_f(tid, bytes, hdferr)
    if (hdferr /= 0) then
      dcpl = -1_hid_t
      return
    end if
    chunk = hdims
    slab = int(bytes, int64)*product(int(hdims(1:rank - 1), int64))
    chunk(rank) = int(max(1_int64, min(int(hdims(rank), int64), max_chunk_bytes/max(slab, 1_int64))), hsize_t)
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, hdferr)
    if (hdferr /= 0) then
      dcpl = -1_hid_t
      return
    end if
    call h5pset_chunk_f(dcpl, rank, chunk, hdferr)
    if (hdferr == 0 .and. deflate > 0) call h5pset_shuffle_f(dcpl, hdferr)
    if (hdferr == 0 .and. deflate > 0) call h5pset_deflate_f(dcpl, deflate, hdferr)
    if (hdferr == 0 .and. checksum) call h5pset_fletcher32_f(dcpl, hdferr)
    if (hdferr /= 0) then
      call h5pclose_f(dcpl, ierr)
      dcpl = -1_hid_t
    end if
  end subroutine chunked_plist

  !> Creates dataset `name`, creating missing intermediate groups, with the
  !> creation property list `dcpl` (none if negative).
  subroutine create_dataset(file, name, tid, sid, lcpl, did, here, err, dcpl)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer(hid_t), intent(in) :: tid, sid
    integer(hid_t), intent(inout) :: lcpl
    integer(hid_t), intent(out) :: did
    character(len=*), intent(in) :: here
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t), intent(in) :: dcpl
    integer :: hdferr
    did = -1_hid_t
    call link_plist(lcpl, hdferr)
    if (hdferr /= 0) then
      call error_set(err, here, 'cannot create link property list for '//where_in(file, name))
      return
    end if
    if (dcpl >= 0) then
      call h5dcreate_f(file%id, name, tid, sid, did, hdferr, dcpl_id=dcpl, lcpl_id=lcpl)
    else
      call h5dcreate_f(file%id, name, tid, sid, did, hdferr, lcpl_id=lcpl)
    end if
    if (hdferr /= 0) then
      did = -1_hid_t
      call error_set(err, here, 'cannot create dataset (exists or bad name) '//where_in(file, name))
    end if
  end subroutine create_dataset

  !> Link-creation property list that creates intermediate groups.
  subroutine link_plist(lcpl, hdferr)
    integer(hid_t), intent(out) :: lcpl
    integer, intent(out) :: hdferr
    integer :: ierr
    call h5pcreate_f(H5P_LINK_CREATE_F, lcpl, hdferr)
    if (hdferr /= 0) then
      lcpl = -1_hid_t
      return
    end if
    call h5pset_create_inter_group_f(lcpl, 1, hdferr)
    if (hdferr /= 0) then
      call h5pclose_f(lcpl, ierr)
      lcpl = -1_hid_t
    end if
  end subroutine link_plist

  !> Fixed-length, null-padded string type of `nchar` bytes.
  subroutine string_type(nchar, tid, hdferr)
    integer(size_t), intent(in) :: nchar
    integer(hid_t), intent(out) :: tid
    integer, intent(out) :: hdferr
    integer :: ierr
    call h5tcopy_f(H5T_FORTRAN_S1, tid, hdferr)
    if (hdferr /= 0) then
      tid = -1_hid_t
      return
    end if
    call h5tset_size_f(tid, nchar, hdferr)
    if (hdferr == 0) call h5tset_strpad_f(tid, H5T_STR_NULLPAD_F, hdferr)
    if (hdferr /= 0) then
      call h5tclose_f(tid, ierr)
      tid = -1_hid_t
    end if
  end subroutine string_type

  !> Checks that `file` is open and `name` non-empty; sets `err` otherwise.
  logical function check_open(file, name, here, err) result(ok)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: here
    type(error_t), allocatable, intent(inout) :: err
    ok = .false.
    if (file%id < 0) then
      call error_set(err, here, 'file not open for dataset '//q(name))
    else if (len_trim(name) == 0) then
      call error_set(err, here, 'empty dataset name in '//q(fpath(file)))
    else
      ok = .true.
    end if
  end function check_open

  !> Opens dataset `name`; false (with `err` set) if it is missing.
  logical function open_dataset(file, name, here, did, err) result(ok)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: here
    integer(hid_t), intent(out) :: did
    type(error_t), allocatable, intent(inout) :: err
    integer :: hdferr
    ok = .false.
    did = -1_hid_t
    if (.not. check_open(file, name, here, err)) return
    if (.not. h5_exists(file, name)) then
      call error_set(err, here, 'no dataset '//where_in(file, name))
      return
    end if
    call h5dopen_f(file%id, name, did, hdferr)
    if (hdferr /= 0) then
      did = -1_hid_t
      call error_set(err, here, 'cannot open dataset '//where_in(file, name)//' (its header is damaged or unreadable)')
      return
    end if
    ok = .true.
  end function open_dataset

  !> Opens dataset `name`, checks its type class and returns its dataspace
  !> and number of elements.
  logical function open_checked(file, name, want_class, class_name, here, did, sid, n, err) result(ok)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, intent(in) :: want_class
    character(len=*), intent(in) :: class_name
    character(len=*), intent(in) :: here
    integer(hid_t), intent(out) :: did, sid
    integer(hsize_t), intent(out) :: n
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: tid
    integer(hsize_t) :: hdims(max_rank), hmax(max_rank)
    integer :: hdferr, tclass, ierr, rank
    ok = .false.
    sid = -1_hid_t
    n = 0
    if (.not. open_dataset(file, name, here, did, err)) return
    call h5dget_type_f(did, tid, hdferr)
    if (hdferr /= 0) then
      call error_set(err, here, 'cannot get type of '//where_in(file, name))
      return
    end if
    call h5tget_class_f(tid, tclass, hdferr)
    call h5tclose_f(tid, ierr)
    if (hdferr /= 0 .or. tclass /= want_class) then
      call error_set(err, here, 'not a '//class_name//' dataset: '//where_in(file, name))
      return
    end if
    call h5dget_space_f(did, sid, hdferr)
    if (hdferr /= 0) then
      sid = -1_hid_t
      call error_set(err, here, 'cannot get dataspace of '//where_in(file, name))
      return
    end if
    ! the size from the dimensions: h5sget_simple_extent_npoints_f reports
    ! an error for a zero-size dataset (HDF5 1.10), which is legitimate here
    call h5sget_simple_extent_ndims_f(sid, rank, hdferr)
    if (hdferr /= 0 .or. rank < 0 .or. rank > max_rank) then
      call error_set(err, here, 'unsupported rank of '//where_in(file, name))
      return
    end if
    n = 1
    if (rank > 0) then
      call h5sget_simple_extent_dims_f(sid, hdims(1:rank), hmax(1:rank), hdferr)
      if (hdferr < 0) then
        call error_set(err, here, 'cannot get size of '//where_in(file, name))
        return
      end if
      n = product(hdims(1:rank))
    end if
    ok = .true.
  end function open_checked

  !> Closes whichever of a dataset, dataspace and datatype are open.
  subroutine release(did, sid, tid)
    integer(hid_t), intent(in) :: did, sid, tid
    integer :: hdferr
    if (tid >= 0) call h5tclose_f(tid, hdferr)
    if (sid >= 0) call h5sclose_f(sid, hdferr)
    if (did >= 0) call h5dclose_f(did, hdferr)
  end subroutine release

  !> The message of a read that failed on an open dataset of known size:
  !> its data are damaged (a checksum that does not match, or storage that
  !> cannot be read or decoded).
  function damaged(file, name) result(s)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: s
    s = 'cannot read '//where_in(file, name)//': its data are damaged (checksum mismatch or unreadable storage)'
  end function damaged

  !> "'name' in 'path'" for error messages.
  function where_in(file, name) result(s)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: s
    s = q(name)//' in '//q(fpath(file))
  end function where_in

  !> The file's path, or "?" if unknown.
  function fpath(file) result(s)
    type(h5_file_t), intent(in) :: file
    character(len=:), allocatable :: s
    if (allocated(file%path)) then
      s = file%path
    else
      s = '?'
    end if
  end function fpath

  !> Quotes a string for messages.
  pure function q(s) result(r)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: r
    r = "'"//s//"'"
  end function q

  ! --------------------------------------------------------------- attributes
  ! Attributes describe a file or a dataset (code version, title, units, a
  ! legend). `object` names the dataset or group that carries the attribute;
  ! '' or '/' is the file itself (its root group). Writing an attribute that
  ! already exists is an error, as for datasets.

  !> Writes `text` (any length, no NUL characters) as the scalar fixed-length
  !> string attribute `name` of `object` ('' or '/': the file).
  subroutine h5_write_attribute_string(file, object, name, text, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: object
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: text
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_write_attribute_string'
    character(len=:), allocatable, target :: buf
    integer(hid_t) :: tid
    integer :: hdferr
    type(c_ptr) :: ptr
    ! HDF5 strings need at least one byte: the empty string is stored as NUL
    if (len(text) == 0) then
      buf = c_null_char
    else
      buf = text
    end if
    call string_type(int(len(buf), size_t), tid, hdferr)
    if (hdferr /= 0) then
      call error_set(err, here, 'cannot create string type for attribute '//attr_where(file, object, name))
      return
    end if
    ptr = c_loc(buf)
    call write_attribute(file, object, name, ptr, tid, [integer ::], here, err)
    call h5tclose_f(tid, hdferr)
  end subroutine h5_write_attribute_string

  !> Writes the scalar double attribute `name` of `object` ('' or '/': the file).
  subroutine h5_write_attribute_real(file, object, name, value, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: object
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: value
    type(error_t), allocatable, intent(inout) :: err
    real(wp), target :: buf
    type(c_ptr) :: ptr
    buf = value
    ptr = c_loc(buf)
    call write_attribute(file, object, name, ptr, h5kind_to_type(wp, H5_REAL_KIND), [integer ::], &
                         'h5_write_attribute_real', err)
  end subroutine h5_write_attribute_real

  !> Writes the one-dimensional default-integer attribute `name` of `object`
  !> ('' or '/': the file) from `values` (at least one value).
  subroutine h5_write_attribute_int(file, object, name, values, err)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: object
    character(len=*), intent(in) :: name
    integer, intent(in) :: values(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_write_attribute_int'
    integer, allocatable, target :: buf(:)
    integer :: stat
    character(len=200) :: msg
    type(c_ptr) :: ptr
    if (size(values) < 1) then
      call error_set(err, here, 'no values for attribute '//attr_where(file, object, name))
      return
    end if
    allocate(buf(size(values)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, here, error_no_memory('attribute '//attr_where(file, object, name)))
      return
    end if
    buf = values
    ptr = c_loc(buf(1))
    call write_attribute(file, object, name, ptr, h5kind_to_type(kind(0), H5_INTEGER_KIND), [size(values)], &
                         here, err)
  end subroutine h5_write_attribute_int

  !> Reads the scalar fixed-length string attribute `name` of `object`
  !> ('' or '/': the file); the text ends at the first NUL.
  subroutine h5_read_attribute_string(file, object, name, text, err)
    use hdf5, only: h5oclose_f, h5aexists_f, h5aopen_f, h5aclose_f, h5aread_f, h5aget_type_f
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: object
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: text
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'h5_read_attribute_string'
    integer(hid_t) :: oid, aid, ftid, mtid
    integer(size_t) :: nchar
    integer :: hdferr, tclass, nul
    logical :: exists, is_var
    character(len=:), allocatable, target :: buf
    type(c_ptr) :: ptr
    text = ''
    is_var = .false.
    oid = -1_hid_t
    aid = -1_hid_t
    ftid = -1_hid_t
    mtid = -1_hid_t
    body: block
      if (.not. open_object(file, object, name, here, oid, err)) exit body
      call h5aexists_f(oid, name, exists, hdferr)
      if (hdferr /= 0 .or. .not. exists) then
        call error_set(err, here, 'no attribute '//attr_where(file, object, name))
        exit body
      end if
      call h5aopen_f(oid, name, aid, hdferr)
      if (hdferr /= 0) then
        aid = -1_hid_t
        call error_set(err, here, 'cannot open attribute '//attr_where(file, object, name))
        exit body
      end if
      call h5aget_type_f(aid, ftid, hdferr)
      if (hdferr /= 0) then
        ftid = -1_hid_t
        call error_set(err, here, 'cannot get the type of attribute '//attr_where(file, object, name))
        exit body
      end if
      call h5tget_class_f(ftid, tclass, hdferr)
      if (hdferr == 0 .and. tclass == H5T_STRING_F) call h5tis_variable_str_f(ftid, is_var, hdferr)
      if (hdferr /= 0 .or. tclass /= H5T_STRING_F) then
        call error_set(err, here, 'not a string attribute: '//attr_where(file, object, name))
        exit body
      end if
      if (is_var) then
        call error_set(err, here, 'variable-length strings unsupported in attribute '//attr_where(file, object, name))
        exit body
      end if
      call h5tget_size_f(ftid, nchar, hdferr)
      if (hdferr /= 0 .or. nchar < 1) then
        call error_set(err, here, 'cannot get the string size of attribute '//attr_where(file, object, name))
        exit body
      end if
      call string_type(nchar, mtid, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot create string type for attribute '//attr_where(file, object, name))
        exit body
      end if
      buf = repeat(c_null_char, int(nchar))
      ptr = c_loc(buf)
      call h5aread_f(aid, mtid, ptr, hdferr)
      if (hdferr /= 0) then
        call error_set(err, here, 'cannot read attribute '//attr_where(file, object, name))
        exit body
      end if
      nul = index(buf, c_null_char)
      if (nul > 0) then
        text = buf(1:nul - 1)
      else
        call move_alloc(buf, text)
      end if
    end block body
    if (mtid >= 0) call h5tclose_f(mtid, hdferr)
    if (ftid >= 0) call h5tclose_f(ftid, hdferr)
    if (aid >= 0) call h5aclose_f(aid, hdferr)
    if (oid >= 0) call h5oclose_f(oid, hdferr)
  end subroutine h5_read_attribute_string

  !> Creates attribute `name` on `object` with type `tid` and shape `dims`
  !> (empty: a scalar) and writes it from the buffer address `ptr`.
  subroutine write_attribute(file, object, name, ptr, tid, dims, here, err)
    use hdf5, only: h5oclose_f, h5acreate_f, h5aclose_f, h5awrite_f
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: object
    character(len=*), intent(in) :: name
    type(c_ptr), intent(inout) :: ptr
    integer(hid_t), intent(in) :: tid
    integer, intent(in) :: dims(:)
    character(len=*), intent(in) :: here
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: oid, sid, aid
    integer(hsize_t) :: hdims(1)
    integer :: hdferr
    oid = -1_hid_t
    sid = -1_hid_t
    aid = -1_hid_t
    body: block
      if (.not. open_object(file, object, name, here, oid, err)) exit body
      if (size(dims) == 0) then
        call h5screate_f(H5S_SCALAR_F, sid, hdferr)
      else
        hdims(1) = int(dims(1), hsize_t)
        call h5screate_simple_f(1, hdims, sid, hdferr)
      end if
      if (hdferr /= 0) then
        sid = -1_hid_t
        call error_set(err, here, 'cannot create dataspace for attribute '//attr_where(file, object, name))
        exit body
      end if
      call h5acreate_f(oid, name, tid, sid, aid, hdferr)
      if (hdferr /= 0) then
        aid = -1_hid_t
        call error_set(err, here, 'cannot create attribute (exists or bad name) '//attr_where(file, object, name))
        exit body
      end if
      call h5awrite_f(aid, tid, ptr, hdferr)
      if (hdferr /= 0) call error_set(err, here, 'cannot write attribute '//attr_where(file, object, name))
    end block body
    if (aid >= 0) call h5aclose_f(aid, hdferr)
    if (sid >= 0) call h5sclose_f(sid, hdferr)
    if (oid >= 0) call h5oclose_f(oid, hdferr)
  end subroutine write_attribute

  !> Opens the object (file root, group or dataset) that attribute `name`
  !> belongs to; false (with `err` set, `oid` negative) if it cannot.
  logical function open_object(file, object, name, here, oid, err) result(ok)
    use hdf5, only: h5oopen_f
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: object, name, here
    integer(hid_t), intent(out) :: oid
    type(error_t), allocatable, intent(inout) :: err
    integer :: hdferr
    ok = .false.
    oid = -1_hid_t
    if (.not. check_open(file, name, here, err)) return
    if (.not. h5_exists(file, object_path(object))) then
      call error_set(err, here, 'no object for attribute '//attr_where(file, object, name))
      return
    end if
    call h5oopen_f(file%id, object_path(object), oid, hdferr)
    if (hdferr /= 0) then
      oid = -1_hid_t
      call error_set(err, here, 'cannot open the object of attribute '//attr_where(file, object, name))
      return
    end if
    ok = .true.
  end function open_object

  !> The HDF5 path of an attribute's object: '' is the root group '/'.
  pure function object_path(object) result(path)
    character(len=*), intent(in) :: object
    character(len=:), allocatable :: path
    if (len_trim(object) == 0) then
      path = '/'
    else
      path = trim(object)
    end if
  end function object_path

  !> "'name' of 'object' in 'path'" for error messages.
  function attr_where(file, object, name) result(s)
    type(h5_file_t), intent(in) :: file
    character(len=*), intent(in) :: object
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: s
    s = q(name)//' of '//q(object_path(object))//' in '//q(fpath(file))
  end function attr_where

end module io_hdf5
