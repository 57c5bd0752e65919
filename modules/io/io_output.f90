!> HDF5 frames and the XDMF time series that lists them.
!>
!> Each frame `<dir>/<name>_NNNNN.h5` holds the node positions `x` and
!> velocities `velocity` (3, ni+1, nj+1, nk+1), the cell fields (ni, nj, nk)
!> density, pressure, energy, sound_speed, viscosity, volume and the integer
!> material index `material`, further cell fields from the caller (with
!> several materials: each material's volume fraction, density, specific
!> internal energy and pressure), the scalars time, step and the conservation
!> totals, and the resolved deck. HDF5 attributes describe the file (code,
!> code_version, build_type, title, unit_system, material_names) and each
!> dataset (`units`, a dimension such as 'mass/length^3' in the deck's unit
!> system; `material` also carries its legend). The XDMF file
!> `<dir>/<name>.xdmf` lists every cell and node field written and is rewritten after
!> every frame. Both are written to a temporary name and renamed, so a reader
!> never sees a partial file.
!>
!> With MPM particles the frame also holds, under `particles/`, their
!> positions `x` and velocities `velocity` (3, np), `density`, `volume`,
!> `mass` (np), the Cauchy stress `stress` (6, np) in XDMF Tensor6 order xx,
!> xy, xz, yy, yz, zz (attribute `components`), and the integers `material`
!> (solid index, legend in its attribute `names`), `body`, `id` (seeding
!> number), `cell` (host cell, i fastest) and `vertex` (0..np-1, the
!> vertex cells' connectivity), and with strength models their history
!> fields (`plastic_strain`, `damage`, `porosity`: units '1'; `temperature`:
!> 'temperature', the deck's temperature unit) and the integer `failed`
!> (1: failed); a second XDMF series, `<dir>/<name>_particles.xdmf`, lists
!> them as a Polyvertex grid per frame with each frame's own count
!> (particles leave through open faces; `out%nparts`), so that ParaView
!> opens the grid and the particles as two datasets. Without particles
!> that file is not written.
!>
!> What a frame holds and how (`frame_options_t`, the deck's &output
!> `fields`, `particle_fields`, `precision` and `compress`): the node
!> coordinates `x` (and `particles/x`, `particles/vertex`) always, the other
!> fields only when chosen (the XDMF lists only those written); with
!> `single` every real array of the grid and the particles, coordinates
!> included, stored as float32 (the scalars time and totals stay double);
!> with `deflate` > 0 every array compressed (shuffle + deflate, `io_hdf5`).
module io_output
  use base_kinds, only: wp, i8
  use base_strings, only: itoa
  use base_errors, only: error_no_memory, error_t, error_set
  use base_build, only: code_version, build_type
  use mesh_grid, only: grid_t
  use hydro_state, only: hydro_t
  use particles_state, only: particles_t
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_LOGICAL, MPI_LOR
  use io_hdf5, only: h5_write_part_real, h5_write_part_int
  use io_hdf5, only: h5_file_t, h5_create, h5_close, h5_write_real, h5_write_int, h5_write_scalar_real, &
                     h5_write_scalar_int, h5_write_string, h5_write_attribute
  use io_xdmf, only: xdmf_write_series, xdmf_write_particles, io_rename
  implicit none
  private
  public :: output_t, output_frame, totals_t, frame_meta_t, material_legend
  public :: frame_options_t, frame_wants, frame_grid_fields, frame_particle_fields
  public :: units_length, units_velocity, units_density, units_pressure, units_specific_energy, &
            units_volume, units_energy, units_none, units_temperature

  !> Dimensions written as each dataset's `units` attribute: the code is
  !> unit-agnostic, so a field's unit is its dimension in the deck's unit
  !> system (the file's `unit_system` attribute, `&run units`).
  character(len=*), parameter :: units_length = 'length', units_velocity = 'length/time', &
    units_density = 'mass/length^3', units_pressure = 'mass/(length*time^2)', &
    units_specific_energy = 'length^2/time^2', units_volume = 'length^3', &
    units_energy = 'mass*length^2/time^2', units_none = '1', units_temperature = 'temperature'

  !> The grid fields a frame may hold, by the names &output `fields` takes:
  !> node velocity and mass, the cell fields, and the per-material cell
  !> fields of a scene with several materials (`vf` is vf_<material> of
  !> every material, `material_density` density_<material>, and so on),
  !> and `max_pressure` (each cell's largest pressure so far), which is
  !> kept and written only when named (not among "all": it is a quantity
  !> of the run that costs a cell array and a restart field).
  character(len=*), parameter :: frame_grid_fields(14) = [character(len=17) :: 'velocity', 'node_mass', &
    'density', 'pressure', 'energy', 'sound_speed', 'viscosity', 'volume', 'material', 'vf', 'material_density', &
    'material_energy', 'material_pressure', 'max_pressure']
  !> The particle fields a frame may hold besides the strength models'
  !> (strength_fields) and `failed` (&output `particle_fields`).
  character(len=*), parameter :: frame_particle_fields(10) = [character(len=8) :: 'velocity', 'density', &
    'volume', 'mass', 'energy', 'stress', 'material', 'body', 'id', 'cell']

  !> How a frame is written: the grid and particle fields chosen
  !> (unallocated: all; empty: the coordinates only), float32 storage of the
  !> real arrays, the deflate level (0: off, 1..9).
  type :: frame_options_t
    character(len=32), allocatable :: fields(:)
    character(len=32), allocatable :: particle_fields(:)
    logical :: single = .false.
    integer :: deflate = 0
  end type frame_options_t

  !> Integral quantities stored with each frame.
  type :: totals_t
    real(wp) :: mass = 0.0_wp, momentum(3) = 0.0_wp, internal = 0.0_wp, kinetic = 0.0_wp
    real(wp) :: energy_initial = 0.0_wp, boundary_work = 0.0_wp
    !> coupled particles (PARTICLES.md §1.12): their internal energy (part of
    !> `internal`), the work of the virtual-fluid pressure on the nodes (given
    !> to the host cells' internal energy) and the rest of the particle-force
    !> work that the constitutive (virtual) strain work does not book, the
    !> decoupling work (both summed over the steps); the change of the
    !> nodal kinetic energy by the particles' transfer at Euler steps
    !> (PARTICLES.md §1.13); the elastic energy failed particles' stresses
    !> gave up (erosion, kept in their internal energy as heat)
    real(wp) :: particle_internal = 0.0_wp, vf_work = 0.0_wp, decoupling_work = 0.0_wp, transfer_energy = 0.0_wp
    real(wp) :: erosion_energy = 0.0_wp
  end type totals_t

  !> Frame bookkeeping.
  type :: output_t
    character(len=:), allocatable :: dir, name
    integer :: nframe = 0
    character(len=256), allocatable :: frames(:)
    real(wp), allocatable :: times(:)
    integer, allocatable :: nparts(:)     !< each frame's particle count
  end type output_t

  !> What describes every frame of a run: the deck's title and unit-system
  !> label ('' when the deck gives none) and the material names, in the
  !> order of their index in the `material` field (1, 2, ...).
  type :: frame_meta_t
    character(len=:), allocatable :: title
    character(len=:), allocatable :: unit_system
    character(len=64), allocatable :: materials(:)
    character(len=64), allocatable :: solids(:)     !< solid names (particles' material index order)
  end type frame_meta_t

  character(len=*), parameter :: real_cell_fields(5) = [character(len=16) :: &
    'density', 'pressure', 'energy', 'sound_speed', 'viscosity']
  character(len=*), parameter :: real_cell_units(5) = [character(len=24) :: &
    units_density, units_pressure, units_specific_energy, units_velocity, units_pressure]

contains

  !> True when `name` is among the fields chosen, `list` (unallocated: all).
  pure logical function frame_wants(list, name)
    character(len=*), allocatable, intent(in) :: list(:)
    character(len=*), intent(in) :: name
    integer :: k
    frame_wants = .true.
    if (.not. allocated(list)) return
    frame_wants = .false.
    do k = 1, size(list)
      if (trim(list(k)) == trim(name)) frame_wants = .true.
    end do
  end function frame_wants

  !> The material legend "1: air, 2: tnt" of `names` (index order).
  pure function material_legend(names) result(legend)
    character(len=*), intent(in) :: names(:)
    character(len=:), allocatable :: legend
    integer :: m
    legend = ''
    do m = 1, size(names)
      if (m > 1) legend = legend//', '
      legend = legend//itoa(m)//': '//trim(names(m))
    end do
  end function material_legend

  !> Writes the next frame and rewrites the XDMF series. `path` returns the
  !> frame's file name.
  !> `material` is each cell's material (the one with the largest volume in
  !> a mixed cell); `extra` holds further cell fields (ncell, size(names)),
  !> e.g. per-material fields, written and listed in the XDMF under `names`,
  !> with the dimension `units`(k) and, where `owner`(k) is not blank, the
  !> name of the material the field belongs to as the attribute `material`.
  !> `pt` (optional): the particles, written when there are any, with
  !> their further fields `pfields` (size(pnames), np) named `pnames`
  !> (the strength models' history, optional) in the dimensions `punits`
  !> (optional; absent: '1'), and the integer failure flags `pfailed` (np,
  !> 1 failed; optional) as `particles/failed`. With `ptotal` and
  !> `pruns` (a decomposed run whose blocks hold their particles), pt and
  !> its fields are this rank's particles, and the frame holds ptotal in
  !> all: this rank's at the places `pruns` gives (2, nrun: 0-based start
  !> and length, increasing), every rank writing its own.
  !> `opts`: which fields, float32 storage, compression (`frame_options_t`;
  !> absent: all fields, doubles, uncompressed).
  !> With `comm` (a decomposed run: every rank calls this with its block g,
  !> h, material and extra) the ranks write the one file together, each its
  !> owned nodes and cells (parallel HDF5, collective), in the layout of one
  !> process; rank 0 writes everything else (pt: the whole run's particles
  !> on every rank, unless `pruns`) and the XDMF series; `path` is the same
  !> on every rank.
  subroutine output_frame(out, g, h, material, names, units, owner, extra, time, step, tot, deck, meta, &
                          path, err, pt, pnames, pfields, comm, node_mass, opts, punits, pfailed, ptotal, pruns)
    type(output_t), intent(inout) :: out
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    integer, intent(in) :: material(:)
    character(len=*), intent(in) :: names(:)
    character(len=*), intent(in) :: units(:)
    character(len=*), intent(in) :: owner(:)
    real(wp), intent(in) :: extra(:, :)
    real(wp), intent(in) :: time
    integer, intent(in) :: step
    type(totals_t), intent(in) :: tot
    character(len=*), intent(in) :: deck
    type(frame_meta_t), intent(in) :: meta
    character(len=:), allocatable, intent(out) :: path
    type(error_t), allocatable, intent(inout) :: err
    type(particles_t), intent(in), optional :: pt
    character(len=*), intent(in), optional :: pnames(:)
    real(wp), intent(in), optional :: pfields(:, :)
    type(MPI_Comm), intent(in), optional :: comm
    real(wp), intent(in), optional :: node_mass(:)
    type(frame_options_t), intent(in), optional :: opts
    character(len=*), intent(in), optional :: punits(:)
    integer, intent(in), optional :: pfailed(:)
    integer, intent(in), optional :: ptotal, pruns(:, :)
    type(frame_options_t) :: o
    type(h5_file_t) :: f
    character(len=256) :: fname
    integer :: np, npw
    character(len=64), allocatable :: fields(:), legend_names(:)
    character(len=16), allocatable :: pscalars(:), pints(:), pvectors(:), ptensors(:), nodef(:), cellint(:)
    real(wp), allocatable :: legend_values(:), buf(:), prow(:)
    integer, allocatable :: ibuf(:)
    integer :: nd(4), cd(3), ns(4), nc(4), cs(3), cc(3), k, stat, nmat, i, j, l
    logical :: mine, failed, direct
    character(len=200) :: msg

    if (size(units) /= size(names) .or. size(owner) /= size(names) .or. size(extra, 2) /= size(names)) then
      call error_set(err, 'output_frame', 'names, units, owner and extra fields differ in number')
      return
    end if
    if (present(opts)) o = opts
    if (present(punits) .and. present(pnames)) then
      if (size(punits) /= size(pnames)) then
        call error_set(err, 'output_frame', 'pnames and punits differ in number')
        return
      end if
    end if
    nmat = 0
    if (allocated(meta%materials)) nmat = size(meta%materials)
    write(fname, '(a,"_",i5.5,".h5")') out%name, out%nframe
    path = out%dir//'/'//trim(fname)
    ! the whole grid's shapes (of the nodes with their 3 components, of the
    ! cells) and this block's part of them: the nodes it counts and the
    ! cells it owns (all of them on one process)
    nd = [3, g%gn + 1]
    cd = g%gn
    ns = [0, g%ulo + g%off]
    nc = [3, g%nhi - g%ulo + 1]
    cs = g%clo - 1 + g%off
    cc = g%chi - g%clo + 1
    ! (its size, about, for the free-space check of a file of several ranks:
    ! coordinates, velocities, cell fields, particles, 4 KiB per dataset)
    np = 0
    if (present(pt)) np = pt%np
    ! (the frame's particles: this rank's, or every rank's with pruns)
    npw = np
    if (present(ptotal)) npw = ptotal
    if (present(pruns) .neqv. present(ptotal)) then
      call error_set(err, 'output_frame', 'ptotal and pruns go together')
      return
    end if
    k = 0
    if (present(pnames)) k = size(pnames)
    ! A block without ghosts (one process) stores its nodes and cells in
    ! the file's order: its arrays are written as they are. A block with
    ! ghosts copies its part into one buffer, filled in place (an array
    ! constructor would build a temporary of its own beside the state: on
    ! one process that copy was some 100 bytes per cell at the run's peak).
    ! The ranks agree on the buffer's allocation before they create the
    ! file together.
    direct = g%ng == 0 .and. product(nc) == 3*g%nnode .and. product(cc) == g%ncell
    stat = 0
    if (.not. direct) allocate(buf(max(product(nc), product(cc))), ibuf(product(cc)), stat=stat, errmsg=msg)
    mine = stat /= 0
    failed = mine
    if (present(comm)) call MPI_Allreduce(mine, failed, 1, MPI_LOGICAL, MPI_LOR, comm)
    if (failed) then
      if (stat /= 0) then
        call error_set(err, 'output_frame', error_no_memory('the frame''s buffer ('// &
                       itoa(product(nc))//' numbers)'))
      else
        call error_set(err, 'output_frame', 'out of memory on another rank: cannot allocate the frame''s buffer')
      end if
      return
    end if
    call h5_create(f, path//'.tmp', err, comm=comm, need=65536_i8 + len(deck) + &
                   56_i8*product(int(g%gn + 1, i8)) + (8_i8*(6 + size(names)) + 4)*product(int(g%gn, i8)) + &
                   8_i8*np*(16 + k) + 4096_i8*(32 + size(names) + k))
    if (allocated(err)) return
    call put_nodes('x', g%x)
    if (frame_wants(o%fields, 'velocity')) call put_nodes('velocity', h%u)
    if (.not. frame_wants(o%fields, 'node_mass')) then
      continue
    else if (present(node_mass)) then
      call put_scalar('node_mass', node_mass, .true.)
    else
      call put_scalar('node_mass', h%mnode, .true.)
    end if
    if (frame_wants(o%fields, 'density')) call put_scalar('density', h%rho, .false.)
    if (frame_wants(o%fields, 'pressure')) call put_scalar('pressure', h%p, .false.)
    if (frame_wants(o%fields, 'energy')) call put_scalar('energy', h%e, .false.)
    if (frame_wants(o%fields, 'sound_speed')) call put_scalar('sound_speed', h%cs, .false.)
    if (frame_wants(o%fields, 'viscosity')) call put_scalar('viscosity', h%q, .false.)
    if (allocated(err) .or. .not. frame_wants(o%fields, 'material')) then
      continue
    else if (direct) then
      call h5_write_part_int(f, 'material', material, cd, cs, cc, err, deflate=o%deflate)
    else
      k = 0
      do l = g%clo(3), g%chi(3)
        do j = g%clo(2), g%chi(2)
          do i = g%clo(1), g%chi(1)
            k = k + 1
            ibuf(k) = material(g%cell(i, j, l))
          end do
        end do
      end do
      call h5_write_part_int(f, 'material', ibuf, cd, cs, cc, err, deflate=o%deflate)
    end if
    do k = 1, size(names)
      call put_scalar(trim(names(k)), extra(:, k), .false.)
    end do
    if (frame_wants(o%fields, 'volume')) call put_scalar('volume', h%vol, .false.)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'time', time, err)
    if (.not. allocated(err)) call h5_write_scalar_int(f, 'step', step, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/mass', tot%mass, err)
    if (.not. allocated(err)) call h5_write_real(f, 'totals/momentum', tot%momentum, [3], err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/internal_energy', tot%internal, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/kinetic_energy', tot%kinetic, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/initial_energy', tot%energy_initial, err)
    if (.not. allocated(err)) call h5_write_scalar_real(f, 'totals/boundary_work', tot%boundary_work, err)
    if (.not. allocated(err)) call h5_write_string(f, 'deck', deck, err)
    if (.not. allocated(err)) call write_attributes(f, names, units, owner, meta, o, err)
    if (.not. allocated(err) .and. npw > 0) call write_particles(f, pt, meta, o, err, pruns, npw)
    ! the particle fields written, by kind, for the XDMF
    pvectors = pick([character(len=16) :: 'velocity'])
    pscalars = pick([character(len=16) :: 'density', 'volume', 'mass', 'energy'])
    pints = pick([character(len=16) :: 'material', 'body', 'id', 'cell'])
    ptensors = pick([character(len=16) :: 'stress'])
    if (present(pnames) .and. npw > 0) then
      do k = 1, size(pnames)
        if (.not. frame_wants(o%particle_fields, pnames(k))) cycle
        ! (a row of pfields, copied into a contiguous array of its own)
        prow = pfields(k, :)
        call put_particles_real(f, trim(pnames(k)), prow, [np], o, err, pruns, npw)
        if (allocated(err)) cycle
        if (present(punits)) then
          call h5_write_attribute(f, 'particles/'//trim(pnames(k)), 'units', trim(punits(k)), err)
        else
          call h5_write_attribute(f, 'particles/'//trim(pnames(k)), 'units', units_none, err)
        end if
        pscalars = [character(len=16) :: pscalars, pnames(k)]
      end do
    end if
    if (present(pfailed) .and. npw > 0 .and. frame_wants(o%particle_fields, 'failed')) then
      call put_particles_int(f, 'failed', pfailed, np, o, err, pruns, npw)
      pints = [character(len=16) :: pints, 'failed']
    end if
    if (allocated(err)) then
      block
        type(error_t), allocatable :: err2
        call h5_close(f, err2)
      end block
      return
    end if
    call h5_close(f, err)
    if (allocated(err)) return
    if (f%rank == 0) call io_rename(path//'.tmp', path, err)
    if (allocated(err)) return

    out%nframe = out%nframe + 1
    if (.not. allocated(out%frames)) then
      out%frames = [character(len=256) ::]
      out%times = [real(wp) ::]
    end if
    if (.not. allocated(out%nparts)) out%nparts = [integer ::]
    out%frames = [character(len=256) :: out%frames, fname]
    out%times = [out%times, time]
    out%nparts = [out%nparts, npw]
    if (f%rank /= 0) return   ! (rank 0 writes the series)
    allocate(fields(0), legend_names(nmat), legend_values(nmat), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'output_frame', error_no_memory('the field list'))
      return
    end if
    ! (the XDMF lists the fields written, in the order of the frames' datasets)
    do k = 1, size(real_cell_fields)
      if (frame_wants(o%fields, real_cell_fields(k))) fields = [character(len=64) :: fields, real_cell_fields(k)]
    end do
    fields = [character(len=64) :: fields, names]
    if (frame_wants(o%fields, 'volume')) fields = [character(len=64) :: fields, 'volume']
    nodef = [character(len=16) ::]
    if (frame_wants(o%fields, 'velocity')) nodef = [character(len=16) :: 'velocity']
    cellint = [character(len=16) ::]
    if (frame_wants(o%fields, 'material')) cellint = [character(len=16) :: 'material']
    ! the legend as field data: ParaView lists "material 1: air" = 1, ...
    do k = 1, nmat
      legend_names(k) = 'material '//itoa(k)//': '//trim(meta%materials(k))
      legend_values(k) = real(k, wp)
    end do
    call xdmf_write_series(out%dir//'/'//out%name//'.xdmf', out%frames, out%times, &
                           g%gn(1), g%gn(2), g%gn(3), nodef, fields, err, &
                           int_cell_fields=cellint, &
                           field_names=legend_names, field_values=legend_values, &
                           info_names=[character(len=16) :: 'code', 'code_version', 'build_type', 'title', &
                                       'unit_system', 'material_names'], &
                           info_values=[character(len=1024) :: 'lsalepm', code_version, build_type, &
                                        meta_text(meta%title), meta_text(meta%unit_system), &
                                        material_legend(legend_source(meta))], real_bytes=merge(4, 8, o%single))
    ! the particles: a series of their own, so that readers open two datasets
    if (.not. allocated(err) .and. any(out%nparts > 0)) &
      call xdmf_write_particles(out%dir//'/'//out%name//'_particles.xdmf', out%frames, out%times, out%nparts, &
                                err, vectors=pvectors, scalars=pscalars, ints=pints, tensors=ptensors, &
                                info_names=[character(len=16) :: 'code', 'code_version', 'build_type', 'title', &
                                            'unit_system', 'solid_names'], &
                                info_values=[character(len=1024) :: 'lsalepm', code_version, build_type, &
                                             meta_text(meta%title), meta_text(meta%unit_system), &
                                             material_legend(solid_source(meta))], real_bytes=merge(4, 8, o%single))
  contains
    !> The particle fields of `list` that the frame holds.
    function pick(list) result(chosen)
      character(len=*), intent(in) :: list(:)
      character(len=16), allocatable :: chosen(:)
      integer :: m
      chosen = [character(len=16) ::]
      do m = 1, size(list)
        if (frame_wants(o%particle_fields, list(m))) chosen = [character(len=16) :: chosen, list(m)]
      end do
    end function pick

    !> Node array a(3, nnode): this block's part.
    subroutine put_nodes(name, a)
      character(len=*), intent(in) :: name
      real(wp), intent(in) :: a(:, :)
      integer :: m
      if (allocated(err)) return
      if (direct) then
        call h5_write_part_real(f, name, a, nd, ns, nc, err, single=o%single, deflate=o%deflate)
        return
      end if
      m = 0
      do l = g%ulo(3), g%nhi(3)
        do j = g%ulo(2), g%nhi(2)
          do i = g%ulo(1), g%nhi(1)
            buf(m + 1:m + 3) = a(:, g%node(i, j, l))
            m = m + 3
          end do
        end do
      end do
      call h5_write_part_real(f, name, buf, nd, ns, nc, err, single=o%single, deflate=o%deflate)
    end subroutine put_nodes

    !> Node array a(nnode) (nodes) or cell array a(ncell): this block's
    !> part.
    subroutine put_scalar(name, a, nodes)
      character(len=*), intent(in) :: name
      real(wp), intent(in) :: a(:)
      logical, intent(in) :: nodes
      integer :: m, lo(3), hi(3)
      if (allocated(err)) return
      if (nodes .and. direct) then
        call h5_write_part_real(f, name, a, nd(2:4), ns(2:4), nc(2:4), err, single=o%single, deflate=o%deflate)
        return
      else if (direct) then
        call h5_write_part_real(f, name, a, cd, cs, cc, err, single=o%single, deflate=o%deflate)
        return
      end if
      lo = merge(g%ulo, g%clo, nodes)
      hi = merge(g%nhi, g%chi, nodes)
      m = 0
      do l = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            m = m + 1
            if (nodes) then
              buf(m) = a(g%node(i, j, l))
            else
              buf(m) = a(g%cell(i, j, l))
            end if
          end do
        end do
      end do
      if (nodes) then
        call h5_write_part_real(f, name, buf, nd(2:4), ns(2:4), nc(2:4), err, single=o%single, deflate=o%deflate)
      else
        call h5_write_part_real(f, name, buf, cd, cs, cc, err, single=o%single, deflate=o%deflate)
      end if
    end subroutine put_scalar
  end subroutine output_frame

  !> The particles' datasets chosen by `o` and their attributes (module
  !> notes); the positions and the vertex numbers always.
  subroutine write_particles(f, pt, meta, o, err, runs, total)
    type(h5_file_t), intent(in) :: f
    type(particles_t), intent(in) :: pt
    type(frame_meta_t), intent(in) :: meta
    type(frame_options_t), intent(in) :: o
    type(error_t), allocatable, intent(inout) :: err
    !> (`output_frame`'s pruns and ptotal: pt this rank's share)
    integer, intent(in), optional :: runs(:, :), total
    ! Voigt (xx, yy, zz, yz, xz, xy) to XDMF Tensor6 (xx, xy, xz, yy, yz, zz)
    integer, parameter :: tensor6(6) = [1, 6, 5, 2, 4, 3]
    integer :: np, k, r
    np = pt%np
    call put_real('x', pt%x, [3, np], units_length)
    ! (each particle's place in the frame)
    if (present(runs)) then
      call put_particles_int(f, 'vertex', [((runs(1, r) + k, k = 0, runs(2, r) - 1), r = 1, size(runs, 2))], np, &
                             o, err, runs, total, always=.true.)
    else
      call put_particles_int(f, 'vertex', [(k - 1, k = 1, np)], np, o, err, always=.true.)
    end if
    call put_real('velocity', pt%v, [3, np], units_velocity)
    call put_real('density', pt%rho, [np], units_density)
    call put_real('volume', pt%vol, [np], units_volume)
    call put_real('mass', pt%m, [np], 'mass')
    call put_real('energy', pt%e, [np], units_specific_energy)
    call put_real('stress', pt%stress(tensor6, :), [6, np], units_pressure)
    if (.not. allocated(err) .and. frame_wants(o%particle_fields, 'stress')) &
      call h5_write_attribute(f, 'particles/stress', 'components', 'xx, xy, xz, yy, yz, zz', err)
    call put_int('material', pt%mat)
    if (.not. allocated(err) .and. allocated(meta%solids) .and. frame_wants(o%particle_fields, 'material')) &
      call h5_write_attribute(f, 'particles/material', 'names', material_legend(meta%solids), err)
    call put_int('body', pt%body)
    call put_int('id', pt%id)
    call put_int('cell', pt%cell)
  contains
    !> The real field particles/<name> of shape dims, if chosen ('x' always).
    subroutine put_real(name, a, dims, units)
      character(len=*), intent(in) :: name, units
      real(wp), intent(in) :: a(*)
      integer, intent(in) :: dims(:)
      if (allocated(err)) return
      if (name /= 'x' .and. .not. frame_wants(o%particle_fields, name)) return
      call put_particles_real(f, name, a, dims, o, err, runs, total)
      if (.not. allocated(err)) call h5_write_attribute(f, 'particles/'//name, 'units', units, err)
    end subroutine put_real

    !> The integer field particles/<name> (np), if chosen.
    subroutine put_int(name, a)
      character(len=*), intent(in) :: name
      integer, intent(in) :: a(:)
      call put_particles_int(f, name, a, np, o, err, runs, total)
    end subroutine put_int
  end subroutine write_particles

  !> The real particle dataset particles/<name> of this rank's shape dims
  !> (the last its particles): the whole dataset, or with runs and total
  !> this rank's runs of a dataset of total particles (`output_frame`).
  subroutine put_particles_real(f, name, a, dims, o, err, runs, total)
    type(h5_file_t), intent(in) :: f
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: a(*)
    integer, intent(in) :: dims(:)
    type(frame_options_t), intent(in) :: o
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: runs(:, :), total
    integer :: last, start(size(dims))
    if (allocated(err)) return
    last = size(dims)
    if (present(runs)) then
      start = 0
      call h5_write_part_real(f, 'particles/'//name, a, [dims(:last - 1), total], start, dims, err, single=o%single, &
                              deflate=o%deflate, runs=runs)
    else
      call h5_write_real(f, 'particles/'//name, a, dims, err, single=o%single, deflate=o%deflate)
    end if
  end subroutine put_particles_real

  !> The integer particle dataset particles/<name> of this rank's np
  !> particles (`put_particles_real`), with its units attribute ('1'), if
  !> the frame's particle fields hold it or `always`.
  subroutine put_particles_int(f, name, a, np, o, err, runs, total, always)
    type(h5_file_t), intent(in) :: f
    character(len=*), intent(in) :: name
    integer, intent(in) :: a(:), np
    type(frame_options_t), intent(in) :: o
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: runs(:, :), total
    logical, intent(in), optional :: always
    logical :: wanted
    if (allocated(err)) return
    wanted = frame_wants(o%particle_fields, name)
    if (present(always)) wanted = wanted .or. always
    if (.not. wanted) return
    if (present(runs)) then
      call h5_write_part_int(f, 'particles/'//name, a, [total], [0], [np], err, deflate=o%deflate, runs=runs)
    else
      call h5_write_int(f, 'particles/'//name, a, [np], err, deflate=o%deflate)
    end if
    if (.not. allocated(err)) call h5_write_attribute(f, 'particles/'//name, 'units', units_none, err)
  end subroutine put_particles_int

  !> The attributes of a frame: the file's identity and each written
  !> dataset's units.
  subroutine write_attributes(f, names, units, owner, meta, o, err)
    type(h5_file_t), intent(in) :: f
    character(len=*), intent(in) :: names(:), units(:), owner(:)
    type(frame_meta_t), intent(in) :: meta
    type(frame_options_t), intent(in) :: o
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, m, nmat
    nmat = 0
    if (allocated(meta%materials)) nmat = size(meta%materials)
    call h5_write_attribute(f, '', 'code', 'lsalepm', err)
    if (.not. allocated(err)) call h5_write_attribute(f, '', 'code_version', code_version, err)
    if (.not. allocated(err)) call h5_write_attribute(f, '', 'build_type', build_type, err)
    if (.not. allocated(err)) call h5_write_attribute(f, '', 'title', meta_text(meta%title), err)
    if (.not. allocated(err)) call h5_write_attribute(f, '', 'unit_system', meta_text(meta%unit_system), err)
    if (.not. allocated(err)) call h5_write_attribute(f, '', 'material_names', &
                                                      material_legend(legend_source(meta)), err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'x', 'units', units_length, err)
    call put_units('velocity', units_velocity)
    call put_units('node_mass', 'mass')
    do k = 1, size(real_cell_fields)
      call put_units(trim(real_cell_fields(k)), trim(real_cell_units(k)))
    end do
    call put_units('material', units_none)
    if (.not. allocated(err) .and. frame_wants(o%fields, 'material')) &
      call h5_write_attribute(f, 'material', 'names', material_legend(legend_source(meta)), err)
    if (.not. allocated(err) .and. nmat > 0 .and. frame_wants(o%fields, 'material')) &
      call h5_write_attribute(f, 'material', 'values', [(m, m = 1, nmat)], err)
    do k = 1, size(names)
      if (.not. allocated(err)) call h5_write_attribute(f, trim(names(k)), 'units', trim(units(k)), err)
      if (len_trim(owner(k)) > 0 .and. .not. allocated(err)) &
        call h5_write_attribute(f, trim(names(k)), 'material', trim(owner(k)), err)
    end do
    call put_units('volume', units_volume)
    if (.not. allocated(err)) call h5_write_attribute(f, 'time', 'units', 'time', err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'step', 'units', units_none, err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'totals/mass', 'units', 'mass', err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'totals/momentum', 'units', 'mass*length/time', err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'totals/internal_energy', 'units', units_energy, err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'totals/kinetic_energy', 'units', units_energy, err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'totals/initial_energy', 'units', units_energy, err)
    if (.not. allocated(err)) call h5_write_attribute(f, 'totals/boundary_work', 'units', units_energy, err)
  contains
    !> The units of the grid field `name`, if it was written.
    subroutine put_units(name, text)
      character(len=*), intent(in) :: name, text
      if (allocated(err) .or. .not. frame_wants(o%fields, name)) return
      call h5_write_attribute(f, name, 'units', text, err)
    end subroutine put_units
  end subroutine write_attributes

  !> `text` if allocated, else ''.
  pure function meta_text(text) result(s)
    character(len=:), allocatable, intent(in) :: text
    character(len=:), allocatable :: s
    if (allocated(text)) then
      s = trim(text)
    else
      s = ''
    end if
  end function meta_text

  !> The solid names of `meta` (none if unset).
  pure function solid_source(meta) result(names)
    type(frame_meta_t), intent(in) :: meta
    character(len=64), allocatable :: names(:)
    if (allocated(meta%solids)) then
      names = meta%solids
    else
      names = [character(len=64) ::]
    end if
  end function solid_source

  !> The material names of `meta` (none if unset).
  pure function legend_source(meta) result(names)
    type(frame_meta_t), intent(in) :: meta
    character(len=64), allocatable :: names(:)
    if (allocated(meta%materials)) then
      names = meta%materials
    else
      names = [character(len=64) ::]
    end if
  end function legend_source
end module io_output
