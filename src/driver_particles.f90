!> Builds the MPM particles of a scene from its &particles groups (none:
!> nothing is allocated): each group seeded from its shape
!> (`particles_seed`, shapes of `mesh_shapes`) or its file of points
!> (`io_points_file`, each point located in the grid by `seed_hosts`),
!> given its solid, density, initial velocity and stress and body id, then
!> all sorted by solid and host cell and binned (`particles_order`).
!>
!> Coupled particles (&hydro particles = 'coupled', the default) also get
!> their virtual-fluid mass m'_p = host density x V_p (frozen through a
!> Lagrangian phase, taken again at each Euler step), the nodes they reach
!> their share of the momentum (`particles_share_velocities`),
!> one history variable (plastic strain), the strength model of each solid
!> and the coupling work arrays; `particles_step` is their Lagrangian step
!> (`particles_lagrange_step`, PARTICLES.md §1.7-1.11, with the nodal
!> time-step guard of §1.11); the
!> `particles_euler_*` hooks are their part of an Euler step (§1.13, Remark 2
!> of Sect. 5.2). A solid with eos = 'mie_gruneisen' gets its
!> EOS in its strength slot (pressure p(rho, e), `particles_lagrange`) and
!> its particles' initial energy from the EOS at their density and the
!> pressure of their initial stress.
!>
!> Energy accounting (§1.12): the conservation report takes the kinetic
!> energy and momentum with the full nodal mass (`state_totals`), the
!> particles' internal energy sum_p m_p e_p (e_p from the constitutive
!> work, `particles_stress_arrays`), the virtual-fluid pressure work given
!> to the host cells (`particles_vf_energy`, inside `lagrange_step`), and
!> the decoupling work (the particle-stress force work on the nodes plus
!> the constitutive work, which cancel where the real and virtual strains
!> and the stresses of both agree) as its own line, in the balance.
module driver_particles
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_no_memory, error_t, error_set, ERR_INPUT, ERR_RUNTIME
  use mesh_grid, only: grid_t, grid_index_t
  use particles_config, only: particles_config_t, particles_file_place
  use particles_euler, only: particles_euler_t, particles_cell_density, &
                             particles_share_velocities, particles_rebuild_nodes, particles_relocate, &
                             particles_occupied, particles_place, particles_first_lost, particles_owned_hosts, &
                             particles_open_far, particles_out_open_face, particles_cells_hold, particles_out_t, &
                             particles_take_out, particles_relocate_rezoned
  use particles_spread, only: particles_support_widths
  use particles_shape, only: particles_locate
  use mesh_geometry, only: hex_volume
  use particles_virtual, only: particles_virtual_fill
  use material_table, only: material_eval_eos
  use particles_seed, only: seed_shape, seed_surface, seed_line, seed_hosts, seed_union, seed_points, rigid_velocity, &
                            seed_bins_t, seed_bins_build
  use io_stl, only: stl_read
  use mesh_surface, only: surface_t, surface_build
  use particles_state, only: particles_t, particles_allocate, particles_order, particles_select, particles_solid_order, &
                             particles_take_fields, particles_cell_counts, particles_places
  use base_sort, only: sorted_runs
  use parallel_comm, only: comm_t, parallel_max, parallel_min, parallel_sum, parallel_nomem
  use parallel_gather, only: cell_prefix, gather_concat, gather_to, scatter_from
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use driver_parallel, only: agree_error
  use parallel_particles, only: parallel_particles_take, parallel_particles_gather, parallel_particles_move, parallel_walks, &
                                parallel_mark_cells
  use particles_nodal, only: particles_budget_t, particles_lagrange_step
  use particles_lagrange, only: particles_work_t, strength_slot_t, particles_work_init, &
                                particles_phase_mass, particles_virtual_masses, particles_slot_start
  use strength_models, only: strength_params_t
  use strength_factory, only: strength_create, strength_nhist
  use strength_jc_flow, only: jc_flow_t
  use strength_gurson, only: gtn_f, gtn_f0
  use strength_random_field, only: random_field_t, random_field_build, random_field_sample, void_fraction_from_field, &
                                   random_field_correlated
  use eos_mie_gruneisen, only: mie_gruneisen_t
  use mesh_boundary, only: bc_t
  use hydro_state, only: nodal_sums, cell_sums
  use io_points_file, only: points_file_read
  use io_log, only: log_t, log_line
  use driver_config, only: config_t, group_shape
  use mesh_halo, only: halo_t
  use driver_state, only: state_t
  implicit none
  private
  public :: build_particles, particles_step, particles_euler_preposition, &
            particles_euler_finish, particles_euler_relocate, particles_euler_couple, particles_take, &
            particles_gathered, particles_blocks_share, count_hosts, particles_euler_fill, particles_euler_blocks, &
            particles_preposition_blocks

  !> One seeded group before assembly.
  type :: seeded_t
    integer, allocatable :: cell(:)
    real(wp), allocatable :: xi(:, :), x(:, :), vol(:)
    !> a list's group (a file's points, a line's): each particle's place in
    !> the list (its seeding order), and the list's length
    integer, allocatable :: list(:)
    integer :: nlist = 0
  end type seeded_t

contains

  !> The particles of every &particles group into st%pt (module notes).
  !> With comm (a decomposed run: `whole_build`) each block seeds its owned cells, numbers its
  !> particles as one process does (the seeding order, group by group and
  !> cell by cell in the whole grid's order: `cell_prefix`; a file's or a
  !> line's points in their list's order), and sends
  !> them to the blocks whose ghost layers hold them
  !> (`parallel_particles_move`); the log's counts and sums are the whole
  !> run's.
  subroutine build_particles(cfg, st, log, err, comm)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    type(comm_t), intent(in), optional :: comm
    type(seeded_t), allocatable :: groups(:)
    type(strength_slot_t), allocatable :: models(:)
    type(seed_bins_t) :: bins
    type(xsum_t) :: vsum(1)
    real(wp) :: axis(3), rho
    integer :: k, i, np, q, stat, nhist, nall(2)
    integer, allocatable :: shared(:), counts(:), ids(:), first(:), total(:)
    logical, allocatable :: owned(:)
    logical :: blocks
    character(len=120) :: note
    character(len=200) :: msg

    if (.not. allocated(cfg%particles)) return
    if (size(cfg%particles) == 0) return
    blocks = present(comm)
    allocate(groups(size(cfg%particles)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'build_particles', error_no_memory('the groups'))
      return
    end if
    ! (a block finds the points of files and lines through bins of its
    ! cells, built once)
    if (blocks .and. any(cfg%particles%shape == 'file' .or. cfg%particles%shape == 'line')) then
      call seed_bins_build(st%g, bins, stat)
      if (stat /= 0) call error_set(err, 'build_particles', error_no_memory('the bins of the block''s cells'))
      call agree_error(comm, err)
      if (allocated(err)) return
    end if
    np = 0
    do k = 1, size(cfg%particles)
      associate (pc => cfg%particles(k), gr => groups(k))
        if (pc%shape == 'file') then
          call seed_file(st, pc, k, gr, bins, err, comm)
        else if (pc%shape == 'stl') then
          call seed_stl(st, pc, k, gr, err)
        else if (pc%shape == 'line') then
          call seed_bar(st, pc, k, gr, bins, err, comm)
        else
          call seed_shape(st%g, group_shape(pc), pc%per_cell, gr%cell, gr%xi, gr%x, gr%vol, err)
        end if
        ! (a block keeps those of its owned cells, a list's group has kept
        ! them; the counts are the run's)
        if (blocks .and. .not. allocated(err) .and. .not. allocated(gr%list)) call owned_only(st%g, gr, err)
        if (blocks) call agree_error(comm, err)
        if (allocated(err)) return
        ! (a solid inside the mapped 1D run would be overrun by what the 1D
        ! run did in its place)
        if (.not. allocated(err) .and. allocated(st%pre1d)) then
          if (allocated(st%pre1d%hit)) then
            if (any(st%pre1d%hit(gr%cell))) call error_set(err, 'the deck has 1 problem(s); nothing was run', &
              '&prerun: &particles('//itoa(k)//') has particles in a cell the 1D run is mapped into (it ran as if '// &
              'the solid were not there): map earlier or give a map_radius short of the solid', ERR_INPUT)
          end if
        end if
        if (blocks) call agree_error(comm, err)
        if (allocated(err)) return
        if (group_count(size(gr%cell)) == 0) then
          call error_set(err, 'the deck has 1 problem(s); nothing was run', '&particles('//itoa(k)//'): the '// &
            trim(pc%shape)//' seeds no particle at per_cell = '//itoa(pc%per_cell)//' (no sub-cell centre '// &
            'lies in it): make it larger or raise per_cell', ERR_INPUT)
          return
        end if
      end associate
    end do
    call union_of_bodies(cfg, groups, shared, err, blocks)
    if (blocks) call agree_error(comm, err)
    if (allocated(err)) return
    if (blocks) then
      counts = [(size(groups(k)%cell), k = 1, size(groups))]
      call parallel_sum(comm, counts)
      call parallel_sum(comm, shared)
      k = findloc(counts, 0, 1)
      if (k > 0) then
        call union_empty(cfg, k, err)
        return
      end if
    end if
    ! the seeding ids (1.. in the whole run, group by group in seeding
    ! order)
    call seeding_ids(st, groups, ids, first, total, err, comm)
    if (blocks) call agree_error(comm, err)
    if (allocated(err)) return
    np = 0
    do k = 1, size(groups)
      np = np + size(groups(k)%cell)
    end do
    nhist = 0
    if (cfg%hydro%particles_coupled) then
      do k = 1, size(cfg%solids)
        nhist = max(nhist, strength_nhist(cfg%solids(k)%strength, cfg%solids(k)%tensile_strength))
      end do
    end if
    call particles_allocate(st%pt, np, size(cfg%solids), nhist, err)
    if (allocated(err)) return
    st%pt%spread = cfg%hydro%particle_gimp
    q = 0
    do k = 1, size(cfg%particles)
      associate (pc => cfg%particles(k), gr => groups(k), p => st%pt)
        rho = pc%density
        if (.not. rho > 0.0_wp) rho = cfg%solids(pc%isolid)%density
        axis = 0.0_wp
        axis(pc%axis) = 1.0_wp
        do i = 1, size(gr%cell)
          q = q + 1
          p%id(q) = ids(q)
          p%mat(q) = pc%isolid
          p%body(q) = pc%body
          p%cell(q) = gr%cell(i)
          p%xi(:, q) = gr%xi(:, i)
          p%x(:, q) = gr%x(:, i)
          p%vol(q) = gr%vol(i)
          p%rho(q) = rho
          p%m(q) = rho*gr%vol(i)
          if (pc%velocity_field == 'rotation') then
            p%v(:, q) = rigid_velocity(pc%velocity, pc%angular_velocity, axis, pc%center, gr%x(:, i))
          else
            p%v(:, q) = pc%velocity
          end if
          p%stress(:, q) = pc%stress
        end do
        note = ''
        if (shared(k) > 0) note = ' (not the '//itoa(shared(k))//' sub-cells an earlier group of the body seeded)'
        ! (the volume summed exactly: the same on any rank count)
        vsum(1) = xsum_t()
        do i = 1, size(gr%cell)
          call xsum_add(vsum(1), gr%vol(i))
        end do
        call st%halo%sums(vsum)
        call log_line(log, 'particles('//itoa(k)//'): '//itoa(group_count(size(gr%cell)))//' particles of solid '''// &
          trim(cfg%solids(pc%isolid)%name)//''', body '//itoa(pc%body)//', volume '//rtoa(xsum_value(vsum(1)))// &
          ', mass '//rtoa(rho*xsum_value(vsum(1)))//trim(note))
      end associate
    end do
    call particles_order(st%pt, st%g%ncell, err)
    if (blocks) call agree_error(comm, err)
    if (allocated(err)) return
    if (st%pt%spread) call particles_support_widths(st%g, st%pt)
    if (cfg%hydro%particles_coupled) then
      call couple_particles(cfg, st, err, .not. blocks)
      if (.not. allocated(err)) then
        call gurson_voids(cfg, st, log, first, total, err, comm)
      end if
    end if
    if (blocks) call agree_error(comm, err)
    if (allocated(err)) return
    nall = [st%pt%np, count_hosts(st%pt, st%g%ncell)]
    if (blocks) then
      ! the block's particles sent to the blocks whose ghost layers hold
      ! them, then the nodes their momentum (`couple_particles`)
      call parallel_sum(comm, nall)
      owned = [(.true., k = 1, st%pt%np)]
      call parallel_particles_move(comm, st%g, merge(2, 1, st%pt%spread), st%pt, owned, err)
      if (.not. allocated(err)) then
        st%pblocks = .true.
        if (allocated(st%pw%models)) call move_alloc(st%pw%models, models)
        call blocks_work(st, models, owned, err)
      end if
      if (.not. allocated(err) .and. cfg%hydro%particles_coupled) &
        call particles_share_velocities(st%g, st%h, st%bc, st%pt, st%pw, st%halo)
      call agree_error(comm, err)
      if (allocated(err)) return
    end if
    call log_line(log, 'particles: '//itoa(nall(1))//' in all, '//itoa(nall(2))// &
                  ' host cells, '//itoa(size(cfg%solids))//' solid(s)')

  contains

    !> A group's particle count, the whole run's.
    integer function group_count(n) result(nw)
      integer, intent(in) :: n
      integer :: a(1)
      a(1) = n
      if (blocks) call parallel_sum(comm, a)
      nw = a(1)
    end function group_count
  end subroutine build_particles

  !> The particles of a seeded group gr in the block's owned cells of g.
  subroutine owned_only(g, gr, err)
    class(grid_index_t), intent(in) :: g
    type(seeded_t), intent(inout) :: gr
    type(error_t), allocatable, intent(inout) :: err
    logical, allocatable :: keep(:)
    integer :: i, ijk(3), stat
    allocate(keep(size(gr%cell)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'build_particles', error_no_memory('work arrays'))
      return
    end if
    do i = 1, size(gr%cell)
      call g%cell_ijk(gr%cell(i), ijk(1), ijk(2), ijk(3))
      keep(i) = g%owns_cell(ijk(1), ijk(2), ijk(3))
    end do
    gr%cell = pack(gr%cell, keep)
    gr%vol = pack(gr%vol, keep)
    gr%xi = reshape(pack(gr%xi, spread(keep, 1, 3)), [3, count(keep)])
    gr%x = reshape(pack(gr%x, spread(keep, 1, 3)), [3, count(keep)])
  end subroutine owned_only

  !> The seeding ids of the groups' particles (ids(q), q in the order the
  !> groups list them): 1.. over the whole run, group by group, each group's
  !> in its seeding order (on one process the order of the lists; on a
  !> block of a decomposed run (comm) the whole grid's cell order, the
  !> places of the block's cells from `cell_prefix`, within a cell the
  !> list's; a list's group by the places in its list on any rank count);
  !> group k's ids are first(k) + 1 .. first(k) + total(k).
  subroutine seeding_ids(st, groups, ids, first, total, err, comm)
    type(state_t), intent(in) :: st
    type(seeded_t), intent(in) :: groups(:)
    integer, allocatable, intent(out) :: ids(:), first(:), total(:)
    type(error_t), allocatable, intent(inout) :: err
    type(comm_t), intent(in), optional :: comm
    integer, allocatable :: cnt(:, :), before(:, :), seen(:)
    integer :: k, i, q, c, ng, stat
    ng = size(groups)
    allocate(ids(sum([(size(groups(k)%cell), k = 1, ng)])), first(ng), total(ng), seen(st%g%ncell), &
             cnt(merge(ng, 0, present(comm)), st%g%ncell), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'build_particles', error_no_memory('the seeding ids'))
      return
    end if
    if (present(comm)) then
      cnt = 0
      do k = 1, ng
        if (allocated(groups(k)%list)) cycle
        do i = 1, size(groups(k)%cell)
          cnt(k, groups(k)%cell(i)) = cnt(k, groups(k)%cell(i)) + 1
        end do
      end do
      call cell_prefix(comm, st%g%grid_index_t, cnt, before, total)
    else
      total = [(size(groups(k)%cell), k = 1, ng)]
    end if
    ! (a list's group: its list's length on any rank count)
    do k = 1, ng
      if (allocated(groups(k)%list)) total(k) = groups(k)%nlist
    end do
    first(1) = 0
    do k = 2, ng
      first(k) = first(k - 1) + total(k - 1)
    end do
    q = 0
    do k = 1, ng
      seen = 0
      do i = 1, size(groups(k)%cell)
        q = q + 1
        if (allocated(groups(k)%list)) then
          ids(q) = first(k) + groups(k)%list(i)
        else if (present(comm)) then
          c = groups(k)%cell(i)
          seen(c) = seen(c) + 1
          ids(q) = first(k) + before(k, c) + seen(c)
        else
          ids(q) = first(k) + i
        end if
      end do
    end do
  end subroutine seeding_ids

  !> The random initial porosity of the particles of each gurson solid with
  !> void_std > 0 (&solid void_*, PARTICLES.md §3), after their models'
  !> hist_init: a Gaussian random field (`strength_random_field`, correlation
  !> length void_length, 0: uncorrelated) over the solid's particles'
  !> bounding box, sampled at the particles (in the uncorrelated limit each
  !> particle takes the normal of the seeded stream at its place among its
  !> solid's particles in seeding-id order: the groups' ids first(k) + 1 ..
  !> first(k) + total(k)) (a 2D field through a grid one cell thick, nk =
  !> 1), mapped to f0 = void_mean + void_std g (or lognormal) truncated to
  !> [1e-6, min(0.5, gtn_fc)]; f and the kept f0 of the history take it.
  !> The log gives the sample's mean, standard deviation and range (exact
  !> sums), the clipped variance share and the number truncated. A restart
  !> reads the history back over these values. With comm, a block's
  !> particles (its owned cells'), the box, spacing and log the whole run's.
  subroutine gurson_voids(cfg, st, log, first, total, err, comm)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    integer, intent(in) :: first(:), total(:)
    type(error_t), allocatable, intent(inout) :: err
    type(comm_t), intent(in), optional :: comm
    type(random_field_t) :: field
    type(xsum_t) :: acc(2)
    integer, allocatable :: order(:), place(:)
    real(wp), allocatable :: xs(:, :), g(:), f0(:), stream(:), none(:, :), xall(:), gall(:)
    real(wp) :: lo(3), hi(3), vmin(1), clipped(1), fm, fs, range(2)
    integer, allocatable :: held(:)
    integer :: s, n(2), ntrunc, stat, q, k, j, root
    logical :: lattice, builder, local
    character(len=200) :: msg
    do s = 1, size(cfg%solids)
      associate (sc => cfg%solids(s), p => st%pt)
        if (trim(sc%strength) /= 'gurson' .or. .not. sc%void_std > 0.0_wp) cycle
        n(1) = sum(total, mask=[(cfg%particles(k)%isolid == s, k = 1, size(total))])
        if (n(1) == 0) cycle
        order = [(q, q = p%mat_start(s), p%mat_start(s + 1) - 1)]
        allocate(xs(3, size(order)), g(size(order)), f0(size(order)), place(size(order)), stat=stat, errmsg=msg)
        if (stat /= 0) then
          call error_set(err, 'gurson_voids', error_no_memory('the void field''s work arrays'))
          return
        end if
        xs = p%x(:, order)
        lo = huge(1.0_wp)
        hi = -huge(1.0_wp)
        vmin = huge(1.0_wp)
        if (size(order) > 0) then
          lo = minval(xs, dim=2)
          hi = maxval(xs, dim=2)
          vmin = minval(p%vol(order))
        end if
        if (present(comm)) then
          call parallel_min(comm, lo)
          call parallel_max(comm, hi)
          call parallel_min(comm, vmin)
        end if
        if (st%g%gn(3) == 1) then
          ! plane strain, one cell thick: a 2D field
          hi(3) = lo(3)
          xs(3, :) = lo(3)
        end if
        ! (a Gaussian field: each rank builds the part around its own
        ! particles, the whole field's values there (`random_field_build`);
        ! an exponential one: a decomposed run builds the whole grid on one
        ! rank, the one whose block holds the fewest stored cells and
        ! particles (the least state beside the field), not on each: the
        ! others send it their particles' places and take its samples back,
        ! the bits one process samples)
        lattice = random_field_correlated(sc%void_covariance, sc%void_length)
        local = lattice .and. trim(sc%void_covariance) == 'gaussian'
        builder = .true.
        root = 0
        if (present(comm) .and. lattice .and. .not. local) then
          call gather_concat(comm, [st%g%ncell + p%np], held)
          root = minloc(held, 1) - 1
          builder = comm%rank == root
        end if
        clipped = -huge(1.0_wp)
        if (local .and. size(order) > 0) then
          call random_field_build(lo, hi, vmin(1)**(1.0_wp/3.0_wp), sc%void_length, sc%void_covariance, &
                                  sc%void_seed, field, clipped(1), err, box_lo=minval(xs, dim=2), box_hi=maxval(xs, dim=2))
          if (allocated(err)) call void_field_input(sc%where, sc%name, sc%void_length, err)
        else if (builder .and. .not. local) then
          call random_field_build(lo, hi, vmin(1)**(1.0_wp/3.0_wp), sc%void_length, sc%void_covariance, &
                                  sc%void_seed, field, clipped(1), err)
          ! (found only now: the field's box and spacing are the seeded particles')
          if (allocated(err)) call void_field_input(sc%where, sc%name, sc%void_length, err)
        end if
        if (present(comm)) then
          call agree_error(comm, err)
          call parallel_max(comm, clipped)
        end if
        if (allocated(err)) return
        ! each particle's place among the solid's in id order
        do q = 1, size(order)
          place(q) = 0
          do k = 1, size(total)
            if (cfg%particles(k)%isolid /= s) cycle
            if (p%id(order(q)) > first(k) .and. p%id(order(q)) <= first(k) + total(k)) then
              place(q) = place(q) + p%id(order(q)) - first(k)
              exit
            end if
            place(q) = place(q) + total(k)
          end do
        end do
        if (lattice .and. present(comm) .and. .not. local) then
          call gather_to(comm, root, reshape(xs, [3*size(order)]), xall)
          allocate(gall(size(xall)/3), stat=stat)
          if (stat /= 0) then
            call error_set(err, 'gurson_voids', error_no_memory('the void field''s samples'))
          else if (builder) then
            call random_field_sample(field, reshape(xall, [3, size(gall)]), gall, err)
          end if
          call agree_error(comm, err)
          if (allocated(err)) return
          call scatter_from(comm, root, gall, g)
          deallocate(xall, gall)
        else if (lattice) then
          if (size(order) > 0) call random_field_sample(field, xs, g, err)
        else
          ! (the stream up to the last place here; x is not read)
          j = 0
          if (size(order) > 0) j = maxval(place)
          allocate(stream(j), none(3, j), stat=stat)
          if (stat /= 0) then
            call error_set(err, 'gurson_voids', error_no_memory('the void field''s stream'))
            return
          end if
          none = 0.0_wp
          call random_field_sample(field, none, stream, err)
          if (.not. allocated(err)) g = stream(place)
          deallocate(stream, none)
        end if
        if (allocated(err)) return
        call void_fraction_from_field(g, sc%void_mean, sc%void_std, sc%void_distribution, f0, ntrunc, err, &
                                      f_max=min(0.5_wp, sc%gtn_fc))
        if (allocated(err)) return
        p%hist(gtn_f, order) = f0
        p%hist(gtn_f0, order) = f0
        ! (the sample's statistics from exact sums: the same on any ranks)
        acc = xsum_t()
        do q = 1, size(f0)
          call xsum_add(acc(1), f0(q))
        end do
        call st%halo%sums(acc(1:1))
        fm = xsum_value(acc(1))/n(1)
        do q = 1, size(f0)
          call xsum_add(acc(2), (f0(q) - fm)**2)
        end do
        call st%halo%sums(acc(2:2))
        fs = sqrt(xsum_value(acc(2))/max(n(1) - 1, 1))
        range = [huge(1.0_wp), -huge(1.0_wp)]
        if (size(f0) > 0) range = [minval(f0), maxval(f0)]
        n(2) = ntrunc
        if (present(comm)) then
          call parallel_min(comm, range(1:1))
          call parallel_max(comm, range(2:2))
          call parallel_sum(comm, n(2:2))
        end if
        call log_line(log, 'gurson voids of solid '''//trim(sc%name)//''': '//itoa(n(1))//' particles, f0 mean '// &
          rtoa(fm)//', std '//rtoa(fs)//', range '//rtoa(range(1))//' .. '//rtoa(range(2))//' ('// &
          trim(sc%void_distribution)//', '//trim(sc%void_covariance)//' covariance, length '//rtoa(sc%void_length)// &
          ', seed '//itoa(sc%void_seed)//'); '//itoa(n(2))//' truncated to [1e-6, '// &
          rtoa(min(0.5_wp, sc%gtn_fc))//'], variance share clipped '//rtoa(clipped(1)))
        deallocate(order, xs, g, f0, place)
      end associate
    end do
  end subroutine gurson_voids

  !> An input error of the void field (its box and spacing are the seeded
  !> particles', so it is found only once they are) as the deck's problem.
  subroutine void_field_input(where, name, void_length, err)
    character(len=*), intent(in) :: where, name
    real(wp), intent(in) :: void_length
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: why
    if (err%category /= ERR_INPUT) return
    why = err%msg   ! (a copy: error_set deallocates err first)
    call error_set(err, 'the deck has 1 problem(s); nothing was run', trim(where)//' &solid '''//trim(name)// &
                   ''': void_length = '//rtoa(void_length)//' with these particles: '//why, ERR_INPUT)
  end subroutine void_field_input

  !> The coupling of the particles (module notes): virtual-fluid masses
  !> (Eq. 16, §1.7), strength models, work arrays.
  subroutine couple_particles(cfg, st, err, share)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(error_t), allocatable, intent(inout) :: err
    !> the work arrays and the nodes' share of the momentum too (false: a
    !> block, whose particles go to its neighbours first)
    logical, intent(in) :: share
    integer :: s, stat
    character(len=200) :: msg
    type(strength_params_t) :: par
    allocate(st%pt%mvf(st%pt%np), st%pw%models(size(cfg%solids)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'couple_particles', error_no_memory('the coupling arrays'))
      return
    end if
    call particles_virtual_masses(st%pt, st%h%rho)
    do s = 1, size(cfg%solids)
      associate (sc => cfg%solids(s))
        ! (hjc: its hjc_* values and the solid's density as its rho0)
        par = sc%hjc
        par%k = sc%bulk_modulus
        par%g = sc%shear_modulus
        par%y0 = sc%yield_stress
        par%et = sc%tangent_modulus
        par%failure_strain = sc%failure_strain
        par%tensile_strength = sc%tensile_strength
        par%hjc_rho0 = sc%density
        par%jc = jc_flow_t(a=sc%jc_a, b=sc%jc_b, n=sc%jc_n, c=sc%jc_c, eps0=sc%jc_eps0, m=sc%jc_m, t_room=sc%t_room, &
                           t_melt=sc%t_melt)
        par%jc_cp = sc%specific_heat
        par%jc_chi = sc%taylor_quinney
        par%gurson_q1 = sc%gtn_q1; par%gurson_q2 = sc%gtn_q2; par%gurson_fn = sc%gtn_fn; par%gurson_epsn = sc%gtn_epsn
        par%gurson_sn = sc%gtn_sn; par%gurson_fc = sc%gtn_fc; par%gurson_ff = sc%gtn_ff; par%gurson_f0 = sc%void_mean
        call strength_create(sc%strength, par, st%pw%models(s)%m, err, eos_pressure=trim(sc%eos) == 'mie_gruneisen')
        if (allocated(err)) return
        if (trim(sc%eos) == 'mie_gruneisen') &
          st%pw%models(s)%eos = mie_gruneisen_t(rho0=sc%par%rho0, c0=sc%par%c0, s1=sc%par%s1, gamma0=sc%par%gamma0)
        call particles_slot_start(st%pt, s, st%pw%models(s))
      end associate
      if (allocated(err)) return
    end do
    if (.not. share) return
    call particles_work_init(st%pw, st%g%nnode, st%g%ncell, st%pt%np, st%pt%nhist, err)
    ! the nodes the particles reach start with their share of the momentum
    if (.not. allocated(err)) call particles_share_velocities(st%g, st%h, st%bc, st%pt, st%pw, st%halo)
  end subroutine couple_particles

  !> One Lagrangian step with coupled particles (`particles_lagrange_step`),
  !> its energies booked in the state's totals (PARTICLES.md §1.12).
  subroutine particles_step(cfg, st, dt, work, bad_cell, bad_particle, dt_cell, dt_particle)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    real(wp), intent(inout) :: dt
    real(wp), intent(out) :: work
    integer, intent(out) :: bad_cell, bad_particle
    integer, intent(out), optional :: dt_cell, dt_particle
    type(particles_budget_t) :: b
    call particles_lagrange_step(st%g, st%h, st%bc, st%mats, st%mx, cfg%hydro, st%pt, st%pw, st%halo, dt, work, &
                                 bad_cell, bad_particle, b, dt_cell, dt_particle)
    ! (all zero where the step stopped before the particles' update)
    st%tot%erosion_energy = st%tot%erosion_energy + b%eroded
    st%tot%vf_work = st%tot%vf_work + b%vf_work
    st%tot%decoupling_work = st%tot%decoupling_work - (b%nodal_work - b%vf_work) - b%internal_change
  end subroutine particles_step

  !> A block's particles taken from the whole run's (w, on the whole grid's
  !> index wix: after the scene is built, an Euler step or a restart read;
  !> models the strength models, the whole run's): those whose host cell
  !> is one of the block's owned cells or of the ghost layer around them (two
  !> layers for spread particles, `particles_spread`)
  !> (what its owned nodes need: `particles_lagrange`), in the whole arrays'
  !> order (`parallel_particles_take`), pw%owned marking the ones it owns. The coupling's work arrays are
  !> sized anew.
  subroutine particles_take(st, w, wix, models_in, err)
    type(state_t), intent(inout), target :: st
    type(particles_t), intent(in) :: w
    type(grid_index_t), intent(in) :: wix
    type(strength_slot_t), allocatable, intent(in) :: models_in(:)
    type(error_t), allocatable, intent(inout) :: err
    logical, allocatable :: owned(:)
    ! (spread particles reach the owned nodes from the second ghost layer)
    call parallel_particles_take(w, wix, st%g, merge(2, 1, w%spread), st%pt, owned, err)
    if (allocated(err)) return
    st%pblocks = .true.
    call blocks_work(st, models_in, owned, err)
  end subroutine particles_take

  !> The coupling's work arrays of a block's particles sized anew, with the
  !> strength models (models_in) and pw%owned (owned, moved in).
  subroutine blocks_work(st, models_in, owned, err)
    type(state_t), intent(inout) :: st
    type(strength_slot_t), allocatable, intent(in) :: models_in(:)
    logical, allocatable, intent(inout) :: owned(:)
    type(error_t), allocatable, intent(inout) :: err
    type(strength_slot_t), allocatable :: models(:)
    st%pw = particles_work_t()
    if (allocated(models_in)) then
      models = models_in
      call particles_work_init(st%pw, st%g%nnode, st%g%ncell, st%pt%np, st%pt%nhist, err)
      if (allocated(err)) return
      call move_alloc(models, st%pw%models)
    end if
    call move_alloc(owned, st%pw%owned)
  end subroutine blocks_work

  !> After the remap of a decomposed run's Euler step (PARTICLES.md §1.13
  !> items 3-4 on the blocks): each block finds the new host of each
  !> particle it owns among its rezoned stored cells (the walk from the old
  !> host, or from the standard host where the particles were placed in the
  !> standard grid: `particles_relocate` with the block's cuts, the host
  !> the whole grid's walk finds); a walk that would step past a cut, or
  !> that starts beyond the block's stored cells, is taken on by the blocks
  !> beyond (`parallel_walks`), and those particles go to the blocks that
  !> own their hosts. Each particle is then put on its new host's map and
  !> sent to the blocks whose cells or ghost layers hold the new host
  !> (`parallel_particles_move`); then `particles_euler_couple` on each
  !> block. No rank holds more particles than its block's. A particle in no
  !> cell of the whole grid that went out through an open face
  !> (`particles_left_grid`) leaves the run, as on one process
  !> (`particles_out`). done = .false., with nothing changed, where on some
  !> block a walk ends in no cell for another reason (or a walk taken on
  !> does): the caller relocates on the whole grid then. Collective.
  subroutine particles_euler_blocks(pc, st, pe, log, done, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(particles_euler_t), intent(inout) :: pe
    type(log_t), intent(in) :: log
    logical, intent(out) :: done
    type(error_t), allocatable, intent(inout) :: err
    type(particles_t) :: po
    type(particles_out_t) :: out
    type(strength_slot_t), allocatable :: models(:)
    logical, allocatable :: owned(:)
    integer, allocatable :: cell(:), own(:), at_cut(:), start(:), guess(:), hg(:), pick(:), hp(:)
    real(wp), allocatable :: xi(:, :), xp(:, :)
    logical, allocatable :: gone(:)
    integer, allocatable :: cand(:)
    integer :: bad, k, n(3), stat

    associate (g => st%g)
      own = pack([(k, k = 1, st%pt%np)], st%pw%owned)
      po = st%pt
      call particles_select(po, own)
      allocate(cell(po%np), xi(3, po%np), at_cut(po%np), start(po%np), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'particles_euler_blocks', error_no_memory('work arrays'))
        cell = [integer ::]
        start = [integer ::]
      else
        ! (the walk from the standard host where the particles were placed in
        ! the standard grid, as on one process; a standard host beyond the
        ! block's stored cells is minus its number in the whole grid,
        ! `particles_preposition_blocks`: the walk starts there)
        guess = po%cell
        if (pe%on_blocks) guess = pe%guess(own)
        start = merge(-guess, 0, guess < 0)
        guess = max(guess, 1)
        call particles_relocate(g, g%x, po, guess, cell, xi, bad, [g%glo > 0, g%ghi > 0], at_cut)
        ! (a walk that would step past a cut goes on from the cell it stopped
        ! in, on the blocks beyond: `parallel_walks`)
        where (start == 0) start = at_cut
        where (start > 0) cell = -1
      end if
      ! (those the rezone left in no cell of the whole grid, out through an
      ! open face by their host before the step, leave, as on one process)
      cand = pack([(k, k = 1, size(cell))], cell < 0 .and. start == 0)
      call particles_left_grid(pc, g, st%bc, g%x, po%x(:, cand), st%pt%cell(own(cand)), gone)
      cell(pack(cand, gone)) = 0
      n = [merge(1, 0, any(cell < 0 .and. start == 0) .or. stat /= 0), merge(1, 0, any(cell == 0)), count(start > 0)]
      call parallel_max(pc, n(1:2))
      call parallel_sum(pc, n(3:3))
      done = n(1) == 0
      if (.not. done) return
      if (n(3) == 0) then
        if (n(2) > 0) call particles_take_out(po, cell, xi, st%halo, out)
        po%cell = cell
        po%xi = xi
      else
        ! the walks taken on: each particle's host in the whole grid's
        ! numbering, and the particles to the blocks that own their hosts
        pick = pack([(k, k = 1, po%np)], start > 0)
        allocate(hp(size(pick)), xp(3, size(pick)), stat=stat)
        call parallel_nomem(stat, 'the walks taken on')
        call parallel_walks(pc, g, g%x, po%x(:, pick), start(pick), hp, xp)
        ! (one whose walk ends in no cell leaves if it went out through an
        ! open face, as on one process)
        cand = pack([(k, k = 1, size(pick))], hp == 0)
        call particles_left_grid(pc, g, st%bc, g%x, po%x(:, pick(cand)), st%pt%cell(own(pick(cand))), gone)
        n(1:2) = [merge(1, 0, .not. all(gone)), merge(1, 0, any(cell == 0) .or. size(cand) > 0)]
        call parallel_max(pc, n(1:2))
        done = n(1) == 0
        if (.not. done) return
        hg = [(merge(g%global_cell(max(cell(k), 1)), 0, cell(k) > 0), k = 1, po%np)]
        hg(pick) = hp
        xi(:, pick) = xp
        if (n(2) > 0) call particles_take_out(po, hg, xi, st%halo, out)
        po%xi = xi
        owned = [(.true., k = 1, po%np)]
        call parallel_particles_move(pc, g, 0, po, owned, err, hg)
        if (allocated(err)) return
        call log_line(log, '  particles: '//itoa(n(3))//' walks past a block''s cut taken on by the blocks beyond it')
      end if
      call particles_booked_out(st, out, n(2) > 0, pe, log)
      call particles_place(g, po)
      if (po%spread) call particles_support_widths(g, po)
      owned = [(.true., k = 1, po%np)]
      call parallel_particles_move(pc, g, merge(2, 1, po%spread), po, owned, err)
      if (allocated(err)) return
      st%pt = po
      if (allocated(st%pw%models)) models = st%pw%models
      call blocks_work(st, models, owned, err)
      if (allocated(err)) return
      ! (the log's counts, the whole run's)
      n(2:3) = [count(st%pw%owned), particles_owned_hosts(st%g, st%pt)]
      call parallel_sum(pc, n(2:3))
      call particles_euler_couple(st, pe, n(2), n(3), log)
    end associate
  end subroutine particles_euler_blocks

  !> Remark 2 of Sect. 5.2 on the blocks of a decomposed run, before a
  !> smoothing rezone (`particles_euler_preposition` on one process): each
  !> block places the particles it owns in the standard grid x0 (its stored
  !> cells' nodes; the walk from the current host with the block's cuts: the
  !> host the whole grid's walk finds; a walk that would step past a cut is
  !> taken on by the blocks beyond, `parallel_walks`, and logged), and each
  !> cell of that grid that hosts one is marked on the block that owns it
  !> (`parallel_mark_cells`), then on the blocks that store it as a ghost
  !> (the halo). pe%guess (np: each owned particle's standard host, 0 for
  !> the ghost copies; one beyond the block's stored cells as minus its
  !> number in the whole grid) and pe%occupied (the block's stored cells)
  !> are then the block's (pe%on_blocks); one in no cell of the whole
  !> standard grid that went out through an open face
  !> (`particles_left_grid`) occupies none, its guess its host, as on one
  !> process. done = .false., with pe unchanged, where on some block a walk
  !> ends in no cell for another reason (or a walk taken on does): the
  !> caller places them on the whole grid then. Collective.
  subroutine particles_preposition_blocks(pc, st, x0, pe, log, done)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout) :: st
    real(wp), intent(in) :: x0(:, :)
    type(particles_euler_t), intent(inout) :: pe
    type(log_t), intent(in) :: log
    logical, intent(out) :: done
    integer, allocatable :: own(:), host(:), guess(:), cand(:), cells(:), at_cut(:), start(:), pick(:), hp(:)
    logical, allocatable :: mark(:), found(:), gone(:)
    real(wp), allocatable :: occ(:), xp(:, :)
    real(wp) :: xi(3)
    integer :: q, k, m, n(2), stat

    associate (g => st%g, pt => st%pt)
      own = pack([(k, k = 1, pt%np)], st%pw%owned)
      ! (no room: the whole grid's way)
      allocate(host(size(own)), guess(pt%np), found(size(own)), cand(size(own)), cells(size(own)), &
               at_cut(size(own)), start(size(own)), stat=stat)
      n = [merge(1, 0, stat /= 0), 0]
      if (stat /= 0) then
        own = [integer ::]
        host = own
        found = [logical ::]
        cand = own
        cells = own
        at_cut = own
        start = own
      end if
      do q = 1, size(own)
        k = own(q)
        call particles_locate(g, pt%x(:, k), pt%cell(k), host(q), xi, found(q), x0, [g%glo > 0, g%ghi > 0], at_cut(q))
        ! (a walk that would step past a cut goes on from the cell it stopped
        ! in, on the blocks beyond: `parallel_walks`)
        start(q) = 0
        if (.not. found(q) .and. at_cut(q) > 0) start(q) = g%global_cell(at_cut(q))
      end do
      ! (one in no cell of the whole standard grid, out through an open face,
      ! occupies none; the walk after the remap starts at its old host)
      m = 0
      do q = 1, size(own)
        if (found(q) .or. start(q) > 0) cycle
        m = m + 1
        cand(m) = q
      end do
      cand = cand(:m)
      call particles_left_grid(pc, g, st%bc, x0, pt%x(:, own(cand)), pt%cell(own(cand)), gone)
      do q = 1, size(cand)
        if (gone(q)) then
          host(cand(q)) = pt%cell(own(cand(q)))
        else
          n(1) = 1
        end if
      end do
      n(2) = count(start > 0)
      call parallel_max(pc, n(1:1))
      call parallel_sum(pc, n(2:2))
      done = n(1) == 0
      if (.not. done) return
      ! the standard hosts in the whole grid's numbering; those of the walks
      ! taken on beyond the block's stored cells are minus that (the walk
      ! after the remap starts there: `particles_euler_blocks`)
      m = 0
      do q = 1, size(own)
        if (.not. found(q)) cycle
        m = m + 1
        cells(m) = g%global_cell(host(q))
      end do
      if (n(2) > 0) then
        pick = pack([(q, q = 1, size(own))], start > 0)
        allocate(hp(size(pick)), xp(3, size(pick)), stat=stat)
        call parallel_nomem(stat, 'the walks taken on')
        call parallel_walks(pc, g, x0, pt%x(:, own(pick)), start(pick), hp, xp)
        ! (one whose walk ends in no cell, out through an open face, occupies
        ! none, as above)
        cand = pack([(q, q = 1, size(pick))], hp == 0)
        call particles_left_grid(pc, g, st%bc, x0, pt%x(:, own(pick(cand))), pt%cell(own(pick(cand))), gone)
        n(1) = merge(1, 0, .not. all(gone))
        call parallel_max(pc, n(1:1))
        done = n(1) == 0
        if (.not. done) return
        cells = [cells(:m), pack(hp, hp > 0)]
        m = size(cells)
        call log_line(log, '  particles: '//itoa(n(2))//' walks to the standard grid past a block''s cut taken on '// &
                      'by the blocks beyond it')
        do q = 1, size(pick)
          if (hp(q) == 0) then
            host(pick(q)) = pt%cell(own(pick(q)))
          else
            host(pick(q)) = g%stored_cell(hp(q))
            if (host(pick(q)) == 0) host(pick(q)) = -hp(q)
          end if
        end do
      end if
      call parallel_mark_cells(pc, g, cells(:m), mark)
      occ = merge(1.0_wp, 0.0_wp, mark)
      call st%halo%cells(occ)
      pe%occupied = occ > 0.5_wp
      guess = 0
      guess(own) = host
      call move_alloc(guess, pe%guess)
      pe%on_blocks = .true.
    end associate
  end subroutine particles_preposition_blocks

  !> A block's share of a frame or a restart dump that the blocks write
  !> together (`output_frame`'s and `restart_write`'s ptotal and pruns),
  !> with no rank gathering the others' particles: ptw its owned particles
  !> in their order (`particles_take_fields`), host cells numbered in the
  !> whole grid; runs their places (0-based start and length) among all
  !> ranks' in the whole run's order, the one `particles_gathered` gives (by solid, then host cell in the whole grid's order, then id: a
  !> solid's particles of the cells before a cell counted by `cell_prefix`);
  !> total the whole run's count. Collective.
  subroutine particles_blocks_share(pc, st, ptw, runs, total, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(particles_t), intent(out) :: ptw
    integer, allocatable, intent(out) :: runs(:, :)
    integer, intent(out) :: total
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: cnt(:, :), before(:, :), pos(:)
    integer :: tot(st%pt%nsolid), first(st%pt%nsolid), k, s, stat
    logical :: ordered
    call particles_take_fields(st%pt, pack([(k, k = 1, st%pt%np)], st%pw%owned), ptw, err)
    if (allocated(err)) return
    allocate(cnt(st%pt%nsolid, st%g%ncell), pos(ptw%np), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'particles_blocks_share', error_no_memory('the particles'' places'))
      return
    end if
    call particles_cell_counts(ptw, cnt)
    call cell_prefix(pc, st%g%grid_index_t, cnt, before, tot)
    first(1) = 0
    do s = 2, size(first)
      first(s) = first(s - 1) + tot(s - 1)
    end do
    total = sum(tot)
    ! (a block's particles are in the whole run's order within it)
    call particles_places(ptw, first, before, pos, ordered)
    if (.not. ordered) then
      call error_set(err, 'particles_blocks_share', 'a block''s particles are not in the whole run''s order', &
                     ERR_RUNTIME)
      return
    end if
    ptw%cell(:ptw%np) = [(st%g%global_cell(ptw%cell(k)), k = 1, ptw%np)]
    call sorted_runs(pos, runs, stat)
    if (stat /= 0) call error_set(err, 'particles_blocks_share', error_no_memory('the particles'' places'))
  end subroutine particles_blocks_share

  !> The particles of a decomposed run in the whole run's order (ptw, host
  !> cells numbered in the whole grid): `parallel_particles_gather` of the
  !> blocks' owned particles. On every rank (collective).
  subroutine particles_gathered(pc, st, ptw, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(particles_t), intent(inout), target :: ptw
    type(error_t), allocatable, intent(inout) :: err
    call parallel_particles_gather(pc, st%g, st%pt, st%pw%owned, ptw, err)
  end subroutine particles_gathered

  !> Remark 2 of Sect. 5.2, before a smoothing rezone: each particle's host
  !> in the standard (initial) grid x0 by its position, and the cells of
  !> that grid the particles occupy (the smoothing's fixed inner boundary).
  !> A particle outside the standard grid that went out through an open
  !> face (`particles_leave` takes it out after the remap) occupies none;
  !> any other is a runtime failure: the pre-positioning needs the grid box.
  subroutine particles_euler_preposition(st, x0, pe, err)
    type(state_t), intent(in) :: st
    real(wp), intent(in) :: x0(:, :)
    type(particles_euler_t), intent(inout) :: pe
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: xi(:, :)
    integer :: bad, k, stat
    character(len=200) :: msg
    allocate(xi(3, st%pt%np), pe%guess(st%pt%np), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_euler_preposition', error_no_memory('work arrays'))
      return
    end if
    call particles_relocate(st%g, x0, st%pt, st%pt%cell, pe%guess, xi, bad)
    k = particles_first_lost(st%g, st%bc, x0, st%pt, pe%guess)
    if (k > 0) then
      call error_set(err, 'particles_euler_preposition', 'particle '//itoa(st%pt%id(k))//' at ('// &
                     rtoa(st%pt%x(1, k))//', '//rtoa(st%pt%x(2, k))//', '//rtoa(st%pt%x(3, k))// &
                     ') lies outside the initial grid, in which Remark 2 places the particles before smoothing', &
                     ERR_RUNTIME)
      return
    end if
    pe%occupied = particles_occupied(pack(pe%guess, pe%guess > 0), st%g%ncell)
    ! (the walk after the remap starts at the old host of one that left)
    if (bad /= 0) pe%guess = merge(pe%guess, st%pt%cell, pe%guess > 0)
  end subroutine particles_euler_preposition

  !> Before the remap of an Euler step (coupled particles; every block of a
  !> decomposed run): the fluid under the solid takes the state of the fluid
  !> around it (`particles_virtual_fill`), the filled cells' EOS; the energy
  !> this changes (their internal energy, and the nodes' kinetic energy with
  !> the mass they move with, cells' and particles' share) is booked with
  !> the Euler-step transfer. nfill: the cells filled, the whole grid's.
  subroutine particles_euler_fill(st, layers, log, nfill, err)
    type(state_t), intent(inout) :: st
    integer, intent(in) :: layers
    type(log_t), intent(in) :: log
    integer, intent(out) :: nfill
    type(error_t), allocatable, intent(inout) :: err
    logical, allocatable :: filled(:)
    integer, allocatable :: cells(:)
    real(wp) :: e0, e1, m0, m1
    integer :: nlayer, c
    character(len=200) :: line
    call fill_sums(e0, m0)
    call particles_virtual_fill(st%g, st%h, st%pt, st%halo, layers, filled, nfill, nlayer, err)
    if (allocated(err) .or. nfill == 0) return
    cells = pack([(c, c = 1, st%g%ncell)], filled)
    call material_eval_eos(st%mats, st%h%rho, st%h%e, st%h%p, st%h%cs, st%mx, cells, st%h%mat)
    st%pw%mass_ready = .false.
    call fill_sums(e1, m1)
    st%tot%transfer_energy = st%tot%transfer_energy + (e1 - e0)
    write(line, '("  particles: virtual fluid of ",i0," covered cells set from the fluid around the solid (",i0, &
      &" layers), cells'' mass change ",es10.3,", energy change ",es10.3)') nfill, nlayer, m1 - m0, e1 - e0
    call log_line(log, trim(line))

  contains

    !> The owned cells' internal energy plus the nodes' kinetic energy with
    !> the cells' and the particles' share of their mass (en), and the owned
    !> cells' mass (ms), exact.
    subroutine fill_sums(en, ms)
      real(wp), intent(out) :: en, ms
      real(wp) :: ke, p(3), internal
      associate (g => st%g, h => st%h)
        call particles_phase_mass(g, st%pt, st%pw, h%mnode)
        call nodal_sums(g, st%halo, h%mnode + st%pw%mp, h%u, ke, p)
        call cell_sums(g, h, st%halo, ms, internal)
        en = internal + ke
      end associate
    end subroutine fill_sums
  end subroutine particles_euler_fill

  !> After the remap (PARTICLES.md §1.13 items 3-4): `particles_euler_relocate`
  !> and `particles_euler_couple` on the same state (one process, or a
  !> decomposed run's whole grid).
  subroutine particles_euler_finish(st, pe, log, err)
    type(state_t), intent(inout) :: st
    type(particles_euler_t), intent(inout) :: pe
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    call particles_euler_relocate(st, pe, log, err)
    if (.not. allocated(err)) call particles_euler_couple(st, pe, st%pt%np, count_hosts(st%pt, st%g%ncell), log)
  end subroutine particles_euler_finish

  !> After the remap, item 3 (`particles_relocate_rezoned` on st's grid:
  !> one process's, or a decomposed run's whole grid, the same on every
  !> rank): the particles in the rezoned grid, walking from pe%guess (else
  !> from the old hosts); those the rezone left beyond an open face leave
  !> (`particles_booked_out`).
  subroutine particles_euler_relocate(st, pe, log, err)
    type(state_t), intent(inout) :: st
    type(particles_euler_t), intent(inout) :: pe
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    type(particles_out_t) :: out
    logical :: left
    if (.not. allocated(pe%guess)) pe%guess = st%pt%cell
    call particles_relocate_rezoned(st%g, st%bc, st%halo, st%pt, st%pw, pe%guess, out, left, err)
    if (allocated(err)) return
    call particles_booked_out(st, out, left, pe, log)
  end subroutine particles_euler_relocate

  !> After the remap, item 4, on st's grid (one process's, or a block with
  !> the particles of its owned and ghost cells, relocated): coupled
  !> particles get their virtual-fluid masses from the new hosts' densities,
  !> the nodal mass term (Eq. 16) is rebuilt and each node reached by
  !> particles gets u = (m_f u_f + m_p,I vbar_I)/(m_f + m_p,I): u_f the
  !> remapped fluid velocity, m_p,I = sum_p (m_p - m'_p) N_Ip (guarded),
  !> vbar_I the particles' mass-weighted mean velocity at the node (Eq. 30
  !> with v_p), so that a uniform flow carrying a body stays uniform
  !> exactly; then the kinematic conditions, and the change u - vbar given
  !> to the particles (`particles_share_velocities`). The change of the nodal
  !> momentum and kinetic energy this makes (the particles' share rebuilt
  !> from their own velocities, the virtual fluid re-weighted by its new
  !> host density), exact sums over the nodes the blocks count, is logged
  !> and the energy part booked as the transfer energy of the conservation
  !> report. np and hosts: the run's particles and host cells (the log's).
  subroutine particles_euler_couple(st, pe, np, hosts, log)
    type(state_t), intent(inout) :: st
    type(particles_euler_t), intent(in) :: pe
    integer, intent(in) :: np, hosts
    type(log_t), intent(in) :: log
    real(wp) :: ke_f, p_f(3), ke1, p1(3)
    character(len=300) :: line

    associate (h => st%h, pt => st%pt, pw => st%pw)
      if (.not. allocated(pt%mvf)) return
      ! (the particles that came to share a cell even out their density)
      call particles_cell_density(pt, pw%models)
      call particles_rebuild_nodes(st%g, h, st%bc, pt, pw, st%halo, ke_f, p_f, ke1, p1)
      ! (the share of the particles that left went out with them)
      st%tot%transfer_energy = st%tot%transfer_energy + (ke1 + pe%ke_out - ke_f - pe%ke_solid)
      write(line, '("  particles: ",i0," relocated, ",i0," host cells; nodal momentum change ",3es10.2, &
        &", kinetic energy change ",es10.3," (share of the particles rebuilt)")') np, hosts, &
        p1 + pe%p_out - p_f - pe%p_solid, ke1 + pe%ke_out - ke_f - pe%ke_solid
      call log_line(log, trim(line))
    end associate
  end subroutine particles_euler_couple

  !> How many cells host particles (of p, binned on a grid of ncell cells).
  integer function count_hosts(p, ncell)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: ncell
    count_hosts = count(p%cell_start(2:ncell + 1) > p%cell_start(:ncell))
  end function count_hosts

  !> What the particles that left through open faces took out (out,
  !> `particles_take_out`; left: the leaving was taken, else nothing left)
  !> is logged, their energy taken from the boundary work (so the balance
  !> stays closed) and their share of the nodal kinetic energy and momentum
  !> kept in pe (ke_out, p_out, zero when none left).
  subroutine particles_booked_out(st, out, left, pe, log)
    type(state_t), intent(inout) :: st
    type(particles_out_t), intent(in) :: out
    logical, intent(in) :: left
    type(particles_euler_t), intent(inout) :: pe
    type(log_t), intent(in) :: log
    character(len=300) :: line
    pe%ke_out = out%ke
    pe%p_out = out%momentum
    if (.not. left) return
    st%tot%boundary_work = st%tot%boundary_work - out%energy
    write(line, '("  particles: ",i0," left the grid through open faces (mass ",es12.5,", momentum ",3es10.2, &
      &", energy ",es12.5,"); ",i0," remain")') out%left, out%mass, out%momentum, out%energy, out%remain
    call log_line(log, trim(line))
  end subroutine particles_booked_out

  !> Which of this block's particles at xp(3, m) (owned, in no cell a walk
  !> on the block found) left the whole grid through an open face, as one
  !> process finds them (`particles_first_lost`): gone(q) when no cell of
  !> the whole grid with nodes x (each block's stored nodes) may hold
  !> xp(:, q) (every rank tests every rank's points against its own cells,
  !> `particles_cells_hold`) and it went out through an open face by its
  !> host(q) (a cell of the block) or its place (`particles_out_open_face`).
  !> Every rank holds the points of all ranks for the test (3 reals each:
  !> far less than the whole grid's way, which gathers every particle);
  !> each tests against its cells only the points within their boxes'
  !> union. Collective.
  subroutine particles_left_grid(pc, g, bc, x, xp, host, gone)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: x(:, :), xp(:, :)
    integer, intent(in) :: host(:)
    logical, allocatable, intent(out) :: gone(:)
    real(wp), allocatable :: every(:)
    integer, allocatable :: counts(:), held(:)
    real(wp) :: far(6)
    integer :: m, at, q
    m = size(xp, 2)
    allocate(gone(m), source=.false., stat=q)
    call parallel_nomem(q, 'the particles out of the grid')
    far = particles_open_far(g, bc, x)
    call parallel_max(pc, far)
    call gather_concat(pc, [m], counts)
    call gather_concat(pc, reshape(xp, [3*m]), every)
    held = merge(1, 0, particles_cells_hold(g, x, reshape(every, [3, size(every)/3])))
    call parallel_max(pc, held)
    at = sum(counts(:pc%rank))
    gone = [(held(at + q) == 0 .and. particles_out_open_face(g, bc, far, host(q), xp(:, q)), q = 1, m)]
  end subroutine particles_left_grid


  !> A body seeded by several groups is their union: a group's particles in
  !> sub-cells an earlier group of the same body seeded (a column and a slab
  !> meeting in a joint) are dropped (`seed_union`), shared(k) of them from
  !> group k. Groups of points (file, line) are taken as they are. Groups of
  !> one body that share a cell at different per_cell, and a group left
  !> with no particle, are deck mistakes.
  subroutine union_of_bodies(cfg, groups, shared, err, blocks)
    type(config_t), intent(in) :: cfg
    type(seeded_t), intent(inout) :: groups(:)
    integer, allocatable, intent(out) :: shared(:)
    type(error_t), allocatable, intent(inout) :: err
    !> a block's groups (of its owned cells): an empty one is the caller's
    !> to judge, on the whole run's counts
    logical, intent(in) :: blocks
    logical, allocatable :: keep(:)
    logical :: clash
    integer :: j, k, stat
    allocate(shared(size(groups)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'build_particles', error_no_memory('the groups'' counts'))
      return
    end if
    shared = 0
    do k = 2, size(groups)
      associate (pk => cfg%particles(k), gk => groups(k))
        if (pk%shape == 'file' .or. pk%shape == 'line') cycle
        do j = 1, k - 1
          associate (pj => cfg%particles(j), gj => groups(j))
            if (pj%body /= pk%body .or. pj%shape == 'file' .or. pj%shape == 'line') cycle
            allocate(keep(size(gk%cell)), stat=stat)
            if (stat /= 0) then
              call error_set(err, 'build_particles', error_no_memory('the union of a body''s groups'))
              return
            end if
            call seed_union(gj%cell, gj%xi, pj%per_cell, gk%cell, gk%xi, pk%per_cell, keep, clash)
            if (clash) then
              call error_set(err, 'the deck has 1 problem(s); nothing was run', '&particles('//itoa(k)// &
                             ') and &particles('//itoa(j)//') of body '//itoa(pk%body)//' share cells at '// &
                             'different per_cell: give the groups of a body that meet the same per_cell', ERR_INPUT)
              return
            end if
            shared(k) = shared(k) + count(.not. keep)
            gk%cell = pack(gk%cell, keep)
            gk%vol = pack(gk%vol, keep)
            gk%xi = reshape(pack(gk%xi, spread(keep, 1, 3)), [3, count(keep)])
            gk%x = reshape(pack(gk%x, spread(keep, 1, 3)), [3, count(keep)])
            deallocate(keep)
          end associate
        end do
        if (size(gk%cell) == 0 .and. .not. blocks) then
          call union_empty(cfg, k, err)
          return
        end if
      end associate
    end do
  end subroutine union_of_bodies

  !> The deck mistake of a group k whose every particle an earlier group of
  !> its body seeded (`union_of_bodies`).
  subroutine union_empty(cfg, k, err)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: k
    type(error_t), allocatable, intent(inout) :: err
    call error_set(err, 'the deck has 1 problem(s); nothing was run', '&particles('//itoa(k)//'): every '// &
                   'sub-cell of the '//trim(cfg%particles(k)%shape)//' was seeded by an earlier group of body '// &
                   itoa(cfg%particles(k)%body)//' (a body is the union of its groups): remove the group', ERR_INPUT)
  end subroutine union_empty

  !> The particles inside the closed surface of an STL file (`io_stl`,
  !> `mesh_surface`), seeded at per_cell as a shape is.
  subroutine seed_stl(st, pc, k, gr, err)
    type(state_t), intent(in) :: st
    type(particles_config_t), intent(in) :: pc
    integer, intent(in) :: k
    type(seeded_t), intent(inout) :: gr
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: tri(:, :, :)
    type(surface_t) :: surf
    integer :: stat, d
    call stl_read(pc%file_path, tri, err)
    if (allocated(err)) then
      call error_set(err, 'the deck has 1 problem(s); nothing was run', '&particles('//itoa(k)//'): '//err%msg, &
                     ERR_INPUT)
      return
    end if
    do d = 1, 3
      call particles_file_place(pc, tri(:, d, :))
    end do
    call surface_build(tri, surf, stat)
    if (stat /= 0) then
      call error_set(err, 'seed_stl', error_no_memory('the surface of '//itoa(size(tri, 3))//' triangles'))
      return
    end if
    call seed_surface(st%g, surf, pc%per_cell, gr%cell, gr%xi, gr%x, gr%vol, err)
  end subroutine seed_stl

  !> The particles of a file of points: each point's host cell and natural
  !> coordinates (`list_hosts`), its volume from the file or, without a
  !> volume column, the host cell's volume / per_cell^3. A point in no cell
  !> is a deck mistake. Every rank of a decomposed run (comm) reads the file
  !> and keeps the points of its owned cells.
  subroutine seed_file(st, pc, k, gr, bins, err, comm)
    type(state_t), intent(in) :: st
    type(particles_config_t), intent(in) :: pc
    integer, intent(in) :: k
    type(seeded_t), intent(inout) :: gr
    type(seed_bins_t), intent(in) :: bins
    type(error_t), allocatable, intent(inout) :: err
    type(comm_t), intent(in), optional :: comm
    real(wp), allocatable :: vfile(:), x(:, :), xi(:, :), vol(:)
    integer, allocatable :: cell(:)
    integer :: lost, stat

    call points_file_read(pc%file_path, x, vfile, err)
    if (allocated(err)) call error_set(err, 'the deck has 1 problem(s); nothing was run', '&particles('//itoa(k)// &
                                       '): '//err%msg, ERR_INPUT)
    if (present(comm)) call agree_error(comm, err)
    if (allocated(err)) return
    call particles_file_place(pc, x)
    if (size(vfile) > 0) vfile = pc%scale**3*vfile
    call list_hosts(st, x, bins, cell, xi, lost, err, comm)
    if (allocated(err)) return
    if (lost > 0) then
      call error_set(err, 'the deck has 1 problem(s); nothing was run', '&particles('//itoa(k)//'): point '// &
                     itoa(lost)//' of file '''//trim(pc%file)//''' lies in no cell of the grid', ERR_INPUT)
      return
    end if
    allocate(vol(size(cell)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'seed_file', error_no_memory(itoa(size(cell))//' particles'))
      return
    end if
    call seed_points(st%g, cell, vfile, pc%per_cell, vol)
    call listed_group(x, cell, xi, vol, gr)
  end subroutine seed_file

  !> The particles of a bar (&particles shape = 'line', `seed_line`): the
  !> size h of the cell holding the segment's midpoint (found by the block
  !> that owns it in a decomposed run), the pieces' midpoints, each one's
  !> host (`list_hosts`) and volume area L / pieces.
  subroutine seed_bar(st, pc, k, gr, bins, err, comm)
    type(state_t), intent(in) :: st
    type(particles_config_t), intent(in) :: pc
    integer, intent(in) :: k
    type(seeded_t), intent(inout) :: gr
    type(seed_bins_t), intent(in) :: bins
    type(error_t), allocatable, intent(inout) :: err
    type(comm_t), intent(in), optional :: comm
    real(wp), allocatable :: x(:, :), xi(:, :), vol(:)
    integer, allocatable :: cell(:)
    real(wp) :: xn(3, 8), h(1)
    integer :: lost, stat, i

    call list_hosts(st, reshape(0.5_wp*(pc%point + pc%point2), [3, 1]), bins, cell, xi, lost, err, comm)
    if (allocated(err)) return
    h = -1.0_wp
    if (cell(1) > 0) then
      call st%g%gather(cell(1), st%g%x, xn)
      h = abs(hex_volume(xn))**(1.0_wp/3.0_wp)
    end if
    if (present(comm)) call parallel_max(comm, h)
    stat = 0
    if (lost == 0) call seed_line(pc%point, pc%point2, pc%per_cell, h(1), x, stat)
    if (stat /= 0) call error_set(err, 'build_particles', error_no_memory('the particles of a line'))
    if (present(comm)) call agree_error(comm, err)
    if (allocated(err)) return
    if (lost == 0) call list_hosts(st, x, bins, cell, xi, lost, err, comm)
    if (allocated(err)) return
    if (lost > 0) then
      call error_set(err, 'the deck has 1 problem(s); nothing was run', '&particles('//itoa(k)//'): a '// &
                     'point of the line lies in no cell of the grid', ERR_INPUT)
      return
    end if
    vol = [(pc%area*norm2(pc%point2 - pc%point)/real(size(x, 2), wp), i = 1, size(x, 2))]
    call listed_group(x, cell, xi, vol, gr)
  end subroutine seed_bar

  !> The host cells cell(n) and natural coordinates xi(3, n) of a list of
  !> points x(3, n) (`seed_hosts`), and lost, the first point in no cell (0:
  !> none). On a block of a decomposed run (comm; bins: its cells'): the
  !> hosts among the block's owned cells, 0 for the other points, each point
  !> found by the one block that owns its host. Collective.
  subroutine list_hosts(st, x, bins, cell, xi, lost, err, comm)
    type(state_t), intent(in) :: st
    real(wp), intent(in) :: x(:, :)
    type(seed_bins_t), intent(in) :: bins
    integer, allocatable, intent(out) :: cell(:)
    real(wp), allocatable, intent(out) :: xi(:, :)
    integer, intent(out) :: lost
    type(error_t), allocatable, intent(inout) :: err
    type(comm_t), intent(in), optional :: comm
    integer, allocatable :: hits(:)
    integer :: n, stat

    n = size(x, 2)
    lost = 0
    allocate(cell(n), xi(3, n), hits(n), stat=stat)
    if (stat == 0 .and. present(comm)) call seed_hosts(st%g, x, cell, xi, bins)
    if (stat == 0 .and. .not. present(comm)) call seed_hosts(st%g, x, cell, xi)
    if (stat /= 0) call error_set(err, 'build_particles', error_no_memory(itoa(n)//' particles'' hosts'))
    if (present(comm)) call agree_error(comm, err)
    if (allocated(err)) return
    hits = merge(1, 0, cell > 0)
    if (present(comm)) call parallel_sum(comm, hits)
    lost = findloc(hits, 0, 1)
  end subroutine list_hosts

  !> Group gr from a list's points x(3, n) with hosts cell(n) (0: not this
  !> block's), natural coordinates xi and volumes vol: those with a host,
  !> in list order.
  subroutine listed_group(x, cell, xi, vol, gr)
    real(wp), intent(in) :: x(:, :), xi(:, :), vol(:)
    integer, intent(in) :: cell(:)
    type(seeded_t), intent(inout) :: gr
    integer :: i
    gr%nlist = size(cell)
    gr%list = pack([(i, i = 1, size(cell))], cell > 0)
    gr%cell = cell(gr%list)
    gr%xi = xi(:, gr%list)
    gr%x = x(:, gr%list)
    gr%vol = vol(gr%list)
  end subroutine listed_group
end module driver_particles
