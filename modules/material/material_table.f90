!> The materials of a scene and the cells each one fills.
!>
!> For now every cell holds one material (pure cells); the EOS of each
!> material is evaluated once per material over a packed list of its cells.
!> Mixed cells (volume fractions, per-material state) will extend this module.
module material_table
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use eos_base, only: eos_t
  implicit none
  private
  public :: material_t, material_index_cells, material_eval_eos

  !> One material: its name, its EOS and the cells it fills.
  type :: material_t
    character(len=:), allocatable :: name
    class(eos_t), allocatable :: eos
    integer :: ncell = 0
    logical :: fills_all = .false.        !< true when it is the only material
    integer, allocatable :: cells(:)      !< its cells, ascending (unused if fills_all)
    real(wp), allocatable :: wrho(:), we(:), wp_(:), wcs(:)   !< packed work arrays
  end type material_t

contains

  !> Builds each material's cell list from the cell -> material map `mat`.
  subroutine material_index_cells(mats, mat, err)
    type(material_t), intent(inout) :: mats(:)
    integer, intent(in) :: mat(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: m, c, n, stat
    character(len=200) :: msg

    do m = 1, size(mats)
      n = count(mat == m)
      mats(m)%ncell = n
      mats(m)%fills_all = (n == size(mat))
      if (allocated(mats(m)%cells)) deallocate(mats(m)%cells)
      if (allocated(mats(m)%wrho)) deallocate(mats(m)%wrho, mats(m)%we, mats(m)%wp_, mats(m)%wcs)
      if (mats(m)%fills_all) cycle
      allocate(mats(m)%cells(n), mats(m)%wrho(n), mats(m)%we(n), mats(m)%wp_(n), mats(m)%wcs(n), &
               stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'material_index_cells', 'cannot allocate cell list: '//trim(msg))
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
  end subroutine material_index_cells

  !> Pressure and sound speed of every cell from its density and energy,
  !> dispatching on the EOS once per material.
  subroutine material_eval_eos(mats, rho, e, p, cs)
    type(material_t), intent(inout) :: mats(:)
    real(wp), intent(in) :: rho(:), e(:)
    real(wp), intent(inout) :: p(:), cs(:)
    integer :: m

    do m = 1, size(mats)
      if (mats(m)%ncell == 0) cycle
      if (mats(m)%fills_all) then
        call mats(m)%eos%eval(rho, e, p, cs)
      else
        associate (idx => mats(m)%cells)
          mats(m)%wrho = rho(idx)
          mats(m)%we = e(idx)
          call mats(m)%eos%eval(mats(m)%wrho, mats(m)%we, mats(m)%wp_, mats(m)%wcs)
          p(idx) = mats(m)%wp_
          cs(idx) = mats(m)%wcs
        end associate
      end if
    end do
  end subroutine material_eval_eos
end module material_table
