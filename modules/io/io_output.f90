!> HDF5 frames and the XDMF time series that lists them.
!>
!> Each frame `<dir>/<name>_NNNNN.h5` holds the node positions `x` and
!> velocities `velocity` (3, ni+1, nj+1, nk+1), the cell fields (ni, nj, nk)
!> density, pressure, energy, sound_speed, viscosity and material, the scalars
!> time, step and the conservation totals, and the resolved deck. The XDMF file
!> `<dir>/<name>.xdmf` is rewritten after every frame. Both are written to a
!> temporary name and renamed, so a reader never sees a partial file.
module io_output
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use mesh_grid, only: grid_t
  use lagrange_state, only: hydro_t
  use io_hdf5, only: h5_file_t, h5_create, h5_close, h5_write_real, h5_write_scalar_real, &
                     h5_write_scalar_int, h5_write_string
  use io_xdmf, only: xdmf_write_series, io_rename
  implicit none
  private
  public :: output_t, output_frame, totals_t

  !> Integral quantities stored with each frame.
  type :: totals_t
    real(wp) :: mass = 0.0_wp, momentum(3) = 0.0_wp, internal = 0.0_wp, kinetic = 0.0_wp
    real(wp) :: energy_initial = 0.0_wp, boundary_work = 0.0_wp
  end type totals_t

  !> Frame bookkeeping.
  type :: output_t
    character(len=:), allocatable :: dir, name
    integer :: nframe = 0
    character(len=256), allocatable :: frames(:)
    real(wp), allocatable :: times(:)
  end type output_t

  character(len=*), parameter :: cell_fields(6) = [character(len=16) :: &
    'density', 'pressure', 'energy', 'sound_speed', 'viscosity', 'material']
  character(len=*), parameter :: node_fields(1) = [character(len=16) :: 'velocity']

contains

  !> Writes the next frame and rewrites the XDMF series. `path` returns the
  !> frame's file name.
  !> `material` is each cell's material (the one with the largest volume in
  !> a mixed cell); `extra` holds further cell fields (ncell, size(names)),
  !> e.g. volume fractions, written and listed in the XDMF under `names`.
  subroutine output_frame(out, g, h, material, names, extra, time, step, tot, deck, path, err)
    type(output_t), intent(inout) :: out
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    integer, intent(in) :: material(:)
    character(len=*), intent(in) :: names(:)
    real(wp), intent(in) :: extra(:, :)
    real(wp), intent(in) :: time
    integer, intent(in) :: step
    type(totals_t), intent(in) :: tot
    character(len=*), intent(in) :: deck
    character(len=:), allocatable, intent(out) :: path
    type(error_t), allocatable, intent(inout) :: err
    type(h5_file_t) :: f
    character(len=256) :: fname
    character(len=32), allocatable :: fields(:)
    integer :: nd(4), cd(3), k

    write(fname, '(a,"_",i5.5,".h5")') out%name, out%nframe
    path = out%dir//'/'//trim(fname)
    nd = [3, g%ni + 1, g%nj + 1, g%nk + 1]
    cd = [g%ni, g%nj, g%nk]
    call h5_create(f, path//'.tmp', err)
    if (allocated(err)) return
    call h5_write_real(f, 'x', g%x, nd, err)
    if (.not. allocated(err)) call h5_write_real(f, 'velocity', h%u, nd, err)
    if (.not. allocated(err)) call h5_write_real(f, 'density', h%rho, cd, err)
    if (.not. allocated(err)) call h5_write_real(f, 'pressure', h%p, cd, err)
    if (.not. allocated(err)) call h5_write_real(f, 'energy', h%e, cd, err)
    if (.not. allocated(err)) call h5_write_real(f, 'sound_speed', h%cs, cd, err)
    if (.not. allocated(err)) call h5_write_real(f, 'viscosity', h%q, cd, err)
    if (.not. allocated(err)) call h5_write_real(f, 'material', real(material, wp), cd, err)
    do k = 1, size(names)
      if (.not. allocated(err)) call h5_write_real(f, trim(names(k)), extra(:, k), cd, err)
    end do
    if (.not. allocated(err)) call h5_write_real(f, 'volume', h%vol, cd, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'time', time, err)
    if (.not. allocated(err)) call h5_write_scalar_int(f, 'step', step, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/mass', tot%mass, err)
    if (.not. allocated(err)) call h5_write_real(f, 'totals/momentum', tot%momentum, [3], err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/internal_energy', tot%internal, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/kinetic_energy', tot%kinetic, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/initial_energy', tot%energy_initial, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/boundary_work', tot%boundary_work, err)
    if (.not. allocated(err)) call h5_write_string(f, 'deck', deck, err)
    if (allocated(err)) then
      block
        type(error_t), allocatable :: err2
        call h5_close(f, err2)
      end block
      return
    end if
    call h5_close(f, err)
    if (allocated(err)) return
    call io_rename(path//'.tmp', path, err)
    if (allocated(err)) return

    out%nframe = out%nframe + 1
    if (.not. allocated(out%frames)) then
      out%frames = [character(len=256) ::]
      out%times = [real(wp) ::]
    end if
    out%frames = [character(len=256) :: out%frames, fname]
    out%times = [out%times, time]
    allocate(fields(size(cell_fields) + size(names)), stat=k)
    if (k /= 0) then
      call error_set(err, 'output_frame', 'cannot allocate the field list')
      return
    end if
    fields(1:size(cell_fields)) = cell_fields
    do k = 1, size(names)
      fields(size(cell_fields) + k) = names(k)
    end do
    call xdmf_write_series(out%dir//'/'//out%name//'.xdmf', out%frames, out%times, &
                           g%ni, g%nj, g%nk, node_fields, fields, err)
  end subroutine output_frame
end module io_output
