!> The materials of a scene, the pure cells each one fills and its slots in
!> mixed cells, and the EOS evaluation that dispatches once per material.
module material_table
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use eos_base, only: eos_t
  use material_mixed, only: mixed_t
  use base_build, only: build_checks
  implicit none
  private
  public :: material_t, burn_t, material_index_cells, material_eval_eos, material_burn_start, material_burn_at

  !> The programmed burn of an explosive (`material_burn`): per stored cell
  !> its lighting time and burn time, and the burn fraction F1 of the last
  !> `material_burn_at`; the compression burn's reference density and CJ
  !> relative volume. The pressure is max(F1, F2) times the EOS's.
  type :: burn_t
    real(wp), allocatable :: light(:)   !< lighting time t_L (time; huge: never lit)
    real(wp), allocatable :: tau(:)     !< burn time (time, > 0)
    real(wp), allocatable :: f(:)       !< F1 at time t
    real(wp) :: t = 0.0_wp              !< the time F1 is for
    real(wp) :: t0 = 0.0_wp             !< start of the current Lagrangian step (`material_burn_start`)
    real(wp) :: rho0 = 0.0_wp           !< unreacted density (density)
    real(wp) :: v_cj = 0.0_wp           !< CJ relative volume rho0/rho_CJ
  end type burn_t

  !> One material: its name, its EOS, the pure cells it fills and its slots
  !> in mixed cells, and cut-offs applied after every EOS call.
  type :: material_t
    character(len=:), allocatable :: name
    class(eos_t), allocatable :: eos
    real(wp) :: p_min = -huge(1.0_wp)     !< pressure floor (pressure)
    real(wp) :: rho_min = 0.0_wp          !< below this density the pressure is zero (void)
    integer :: ncell = 0
    logical :: fills_all = .false.        !< true when it is the only material and no cell is mixed
    integer, allocatable :: cells(:)      !< its pure cells, ascending (unused if fills_all)
    integer, allocatable :: slots(:)      !< its slots in mixed cells
    real(wp), allocatable :: wrho(:), we(:), wp_(:), wcs(:)   !< packed work arrays
    type(burn_t), allocatable :: burn     !< programmed burn (explosives a &detonation lights)
  end type material_t

contains

  !> Builds each material's pure-cell list from the cell -> material map
  !> `mat` (> 0 pure, <= 0 mixed) and its slot list from the mixed cells.
  !> written (optional, an Euler step's: the only cells whose material may
  !> have changed since the lists were built): where each of them is still
  !> in exactly its own material's list, the pure-cell lists stand and only
  !> the slots are listed again, so that the cost follows the written
  !> cells and the mixed ones, not the grid.
  subroutine material_index_cells(mats, mat, mx, err, written)
    type(material_t), intent(inout) :: mats(:)
    integer, intent(in) :: mat(:)
    type(mixed_t), intent(in) :: mx
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: written(:)
    integer :: m, c, n, stat
    logical :: keep

    keep = present(written)
    if (keep) keep = lists_hold(mats, mat, written)
    if (keep .and. build_checks) then
      ! (a Debug build checks that no other cell changed its material)
      do m = 1, size(mats)
        n = count(mat == m)
        if (n /= mats(m)%ncell) exit
        if (mats(m)%fills_all) cycle
        if (.not. all(mat(mats(m)%cells) == m)) exit
      end do
      if (m <= size(mats)) then
        call error_set(err, 'material_index_cells', 'the cell lists of '//mats(m)%name// &
                       ' changed beyond the written cells')
        return
      end if
    end if
    do m = 1, size(mats)
      if (keep) cycle
      n = count(mat == m)
      mats(m)%ncell = n
      mats(m)%fills_all = (n == size(mat))
      if (allocated(mats(m)%cells)) deallocate(mats(m)%cells)
      if (mats(m)%fills_all) cycle
      allocate(mats(m)%cells(n), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'material_index_cells', error_no_memory('cell list'))
        return
      end if
      n = 0
      do c = 1, size(mat)
        if (mat(c) == m) then
          n = n + 1
          mats(m)%cells(n) = c
        end if
      end do
    end do
    call index_slots(mats, mx, err)
  end subroutine material_index_cells

  !> Whether the pure-cell lists of mats still hold for the cells of
  !> written, the only ones whose material may have changed: each in the
  !> list of its own material (mat > 0) and in no other (lists binary
  !> searched; a list never built fails).
  logical function lists_hold(mats, mat, written) result(ok)
    type(material_t), intent(in) :: mats(:)
    integer, intent(in) :: mat(:), written(:)
    integer :: m, i, c, lo, hi, mid
    logical :: listed
    ok = .true.
    do m = 1, size(mats)
      ok = mats(m)%fills_all .or. allocated(mats(m)%cells)
      if (.not. ok) return
      do i = 1, size(written)
        c = written(i)
        listed = mats(m)%fills_all
        if (.not. listed) then
          lo = 1
          hi = size(mats(m)%cells)
          do while (lo <= hi)
            mid = (lo + hi)/2
            if (mats(m)%cells(mid) == c) then
              listed = .true.
              exit
            end if
            if (mats(m)%cells(mid) < c) then
              lo = mid + 1
            else
              hi = mid - 1
            end if
          end do
        end if
        ok = listed .eqv. (mat(c) == m)
        if (.not. ok) return
      end do
    end do
  end function lists_hold

  !> Each material's slots in the mixed cells of mx, and its packed work
  !> arrays for its pure cells and slots (none where it fills the grid).
  subroutine index_slots(mats, mx, err)
    type(material_t), intent(inout) :: mats(:)
    type(mixed_t), intent(in) :: mx
    type(error_t), allocatable, intent(inout) :: err
    integer :: m, s, n, ns, stat
    do m = 1, size(mats)
      if (allocated(mats(m)%slots)) deallocate(mats(m)%slots)
      if (mats(m)%fills_all) then
        if (allocated(mats(m)%wrho)) deallocate(mats(m)%wrho, mats(m)%we, mats(m)%wp_, mats(m)%wcs)
        cycle
      end if
      ns = 0
      if (mx%nslot > 0) ns = count(mx%mat(1:mx%nslot) == m)
      allocate(mats(m)%slots(ns), stat=stat)
      n = mats(m)%ncell + ns
      if (stat == 0 .and. allocated(mats(m)%wrho)) then
        if (size(mats(m)%wrho) /= n) deallocate(mats(m)%wrho, mats(m)%we, mats(m)%wp_, mats(m)%wcs)
      end if
      if (stat == 0 .and. .not. allocated(mats(m)%wrho)) &
        allocate(mats(m)%wrho(n), mats(m)%we(n), mats(m)%wp_(n), mats(m)%wcs(n), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'material_index_cells', error_no_memory('cell list'))
        return
      end if
      ns = 0
      do s = 1, mx%nslot
        if (mx%mat(s) == m) then
          ns = ns + 1
          mats(m)%slots(ns) = s
        end if
      end do
    end do
  end subroutine index_slots

  !> Pressure and sound speed of every pure cell from its density and energy,
  !> and of every mixed-cell slot from the material's own, dispatching on the
  !> EOS once per material; then the material's cut-offs. With cells (and
  !> mat, each cell's material, <= 0 for a mixed cell): only those pure
  !> cells, and every slot (an Euler step's, which wrote only these cells:
  !> the others' pressures are those of their unchanged states).
  subroutine material_eval_eos(mats, rho, e, p, cs, mx, cells, mat)
    type(material_t), intent(inout) :: mats(:)
    real(wp), intent(in) :: rho(:), e(:)
    real(wp), intent(inout) :: p(:), cs(:)
    type(mixed_t), intent(inout) :: mx
    integer, intent(in), optional :: cells(:), mat(:)
    real(wp), allocatable :: wr(:), we(:), wp_(:), wc(:)
    integer, allocatable :: idx(:)
    integer :: m, n, c, stat

    do m = 1, size(mats)
      if (present(cells)) then
        idx = pack(cells, mat(cells) == m)
        if (.not. mats(m)%fills_all) then
          call eval_list(mats(m), idx, mats(m)%slots, rho, e, p, cs, mx, mats(m)%wrho, mats(m)%we, mats(m)%wp_, &
                         mats(m)%wcs)
          cycle
        end if
        n = size(idx)
        allocate(wr(n), we(n), wp_(n), wc(n), stat=stat)
        if (stat == 0) then
          call eval_list(mats(m), idx, [integer ::], rho, e, p, cs, mx, wr, we, wp_, wc)
          cycle
        end if
        ! (no memory for the list's work arrays: every cell, as without one)
      end if
      if (mats(m)%fills_all) then
        call mats(m)%eos%eval(rho, e, p, cs)
        call cutoffs(mats(m), rho, p)
        if (allocated(mats(m)%burn)) call burn_scale(mats(m)%burn, [(c, c = 1, size(rho))], rho, p)
        cycle
      end if
      call eval_list(mats(m), mats(m)%cells, mats(m)%slots, rho, e, p, cs, mx, mats(m)%wrho, mats(m)%we, mats(m)%wp_, &
                     mats(m)%wcs)
    end do
  end subroutine material_eval_eos

  !> `material_eval_eos` of material mt in the pure cells idx and the
  !> slots sl, through the work arrays wr, we, wp_, wc (at least as long
  !> as both lists).
  subroutine eval_list(mt, idx, sl, rho, e, p, cs, mx, wr, we, wp_, wc)
    type(material_t), intent(inout) :: mt
    integer, intent(in) :: idx(:), sl(:)
    real(wp), intent(in) :: rho(:), e(:)
    real(wp), intent(inout) :: p(:), cs(:)
    type(mixed_t), intent(inout) :: mx
    real(wp), intent(inout) :: wr(:), we(:), wp_(:), wc(:)
    integer :: n, ns
    n = size(idx)
    ns = size(sl)
    if (n + ns == 0) return
    wr(1:n) = rho(idx)
    we(1:n) = e(idx)
    wr(n + 1:n + ns) = mx%rho(sl)
    we(n + 1:n + ns) = mx%e(sl)
    call mt%eos%eval(wr(1:n + ns), we(1:n + ns), wp_(1:n + ns), wc(1:n + ns))
    call cutoffs(mt, wr(1:n + ns), wp_(1:n + ns))
    if (allocated(mt%burn)) then
      call burn_scale(mt%burn, idx, wr(1:n), wp_(1:n))
      call burn_scale(mt%burn, slot_cells(mx, sl), wr(n + 1:n + ns), wp_(n + 1:n + ns))
    end if
    p(idx) = wp_(1:n)
    cs(idx) = wc(1:n)
    mx%p(sl) = wp_(n + 1:n + ns)
    mx%cs(sl) = wc(n + 1:n + ns)
  end subroutine eval_list

  !> The burn fractions of the explosives at time t0 + dt (t0 of
  !> `material_burn_start`): the stages of a Lagrangian step.
  subroutine material_burn_at(mats, dt)
    type(material_t), intent(inout) :: mats(:)
    real(wp), intent(in) :: dt
    integer :: m
    do m = 1, size(mats)
      if (.not. allocated(mats(m)%burn)) cycle
      associate (b => mats(m)%burn)
        b%t = b%t0 + dt
        b%f = min(1.0_wp, max(0.0_wp, (b%t - b%light)/b%tau))
      end associate
    end do
  end subroutine material_burn_at

  !> Sets the time t of the explosives' burn fractions: the start of a
  !> Lagrangian step (its stages then `material_burn_at` t + stage), or the
  !> time of an EOS evaluation outside one (scene, Euler step).
  subroutine material_burn_start(mats, t)
    type(material_t), intent(inout) :: mats(:)
    real(wp), intent(in) :: t
    integer :: m
    do m = 1, size(mats)
      if (allocated(mats(m)%burn)) mats(m)%burn%t0 = t
    end do
    call material_burn_at(mats, 0.0_wp)
  end subroutine material_burn_start

  !> Pressures p(i) of an explosive at densities rho(i) in cells cell(i)
  !> times the burn fraction max(F1, F2) (`material_burn`).
  pure subroutine burn_scale(b, cell, rho, p)
    type(burn_t), intent(in) :: b
    integer, intent(in) :: cell(:)
    real(wp), intent(in) :: rho(:)
    real(wp), intent(inout) :: p(:)
    integer :: i
    real(wp) :: f2
    do i = 1, size(p)
      f2 = min(1.0_wp, max(0.0_wp, (1.0_wp - b%rho0/rho(i))/(1.0_wp - b%v_cj)))
      p(i) = max(b%f(cell(i)), f2)*p(i)
    end do
  end subroutine burn_scale

  !> The grid cell of each of the mixed-cell slots `sl`.
  pure function slot_cells(mx, sl) result(cells)
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: sl(:)
    integer :: cells(size(sl))
    integer :: i, k, lo, hi, mid
    do i = 1, size(sl)
      ! (the mixed cell whose slot range holds sl(i): start is ascending)
      lo = 1; hi = mx%n
      do while (lo < hi)
        mid = (lo + hi + 1)/2
        if (mx%start(mid) <= sl(i)) then
          lo = mid
        else
          hi = mid - 1
        end if
      end do
      k = lo
      cells(i) = mx%cell(k)
    end do
  end function slot_cells

  !> Pressure floor, and zero pressure below the void density.
  subroutine cutoffs(mt, rho, p)
    type(material_t), intent(in) :: mt
    real(wp), intent(in) :: rho(:)
    real(wp), intent(inout) :: p(:)
    integer :: i
    if (mt%p_min < -0.5_wp*huge(1.0_wp) .and. mt%rho_min <= 0.0_wp) return
    do i = 1, size(p)
      p(i) = max(p(i), mt%p_min)
      if (rho(i) < mt%rho_min) p(i) = 0.0_wp
    end do
  end subroutine cutoffs
end module material_table
