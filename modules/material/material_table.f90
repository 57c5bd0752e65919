!> The materials of a scene, the pure cells each one fills and its slots in
!> mixed cells, and the EOS evaluation that dispatches once per material.
module material_table
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use eos_base, only: eos_t
  use material_mixed, only: mixed_t
  implicit none
  private
  public :: material_t, material_index_cells, material_eval_eos

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
  end type material_t

contains

  !> Builds each material's pure-cell list from the cell -> material map
  !> `mat` (> 0 pure, <= 0 mixed) and its slot list from the mixed cells.
  subroutine material_index_cells(mats, mat, mx, err)
    type(material_t), intent(inout) :: mats(:)
    integer, intent(in) :: mat(:)
    type(mixed_t), intent(in) :: mx
    type(error_t), allocatable, intent(inout) :: err
    integer :: m, c, n, ns, s, stat
    character(len=200) :: msg

    do m = 1, size(mats)
      n = count(mat == m)
      ns = 0
      if (mx%nslot > 0) ns = count(mx%mat == m)
      mats(m)%ncell = n
      mats(m)%fills_all = (n == size(mat))
      if (allocated(mats(m)%cells)) deallocate(mats(m)%cells)
      if (allocated(mats(m)%slots)) deallocate(mats(m)%slots)
      if (allocated(mats(m)%wrho)) deallocate(mats(m)%wrho, mats(m)%we, mats(m)%wp_, mats(m)%wcs)
      if (mats(m)%fills_all) cycle
      allocate(mats(m)%cells(n), mats(m)%slots(ns), mats(m)%wrho(n + ns), mats(m)%we(n + ns), &
               mats(m)%wp_(n + ns), mats(m)%wcs(n + ns), stat=stat, errmsg=msg)
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
      ns = 0
      do s = 1, mx%nslot
        if (mx%mat(s) == m) then
          ns = ns + 1
          mats(m)%slots(ns) = s
        end if
      end do
    end do
  end subroutine material_index_cells

  !> Pressure and sound speed of every pure cell from its density and energy,
  !> and of every mixed-cell slot from the material's own, dispatching on the
  !> EOS once per material; then the material's cut-offs.
  subroutine material_eval_eos(mats, rho, e, p, cs, mx)
    type(material_t), intent(inout) :: mats(:)
    real(wp), intent(in) :: rho(:), e(:)
    real(wp), intent(inout) :: p(:), cs(:)
    type(mixed_t), intent(inout) :: mx
    integer :: m, n, ns

    do m = 1, size(mats)
      if (mats(m)%fills_all) then
        call mats(m)%eos%eval(rho, e, p, cs)
        call cutoffs(mats(m), rho, p)
        cycle
      end if
      n = mats(m)%ncell
      ns = size(mats(m)%slots)
      if (n + ns == 0) cycle
      associate (idx => mats(m)%cells, sl => mats(m)%slots)
        mats(m)%wrho(1:n) = rho(idx)
        mats(m)%we(1:n) = e(idx)
        mats(m)%wrho(n + 1:n + ns) = mx%rho(sl)
        mats(m)%we(n + 1:n + ns) = mx%e(sl)
        call mats(m)%eos%eval(mats(m)%wrho, mats(m)%we, mats(m)%wp_, mats(m)%wcs)
        call cutoffs(mats(m), mats(m)%wrho, mats(m)%wp_)
        p(idx) = mats(m)%wp_(1:n)
        cs(idx) = mats(m)%wcs(1:n)
        mx%p(sl) = mats(m)%wp_(n + 1:n + ns)
        mx%cs(sl) = mats(m)%wcs(n + 1:n + ns)
      end associate
    end do
  end subroutine material_eval_eos

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
