!> What follows a remap on the grid it wrote (`remap_euler_step`), the same
!> on one process's grid, a decomposed run's window and the whole grid:
!>  - after each remap (each part of a step in parts): the materials' cell
!>    lists from the new cell materials and mixed cells, and the new mixed
!>    cells' interface planes fitted to their remapped centroids
!>    (`remap_after_planes`: the remap gives each mixed cell its
!>    materials' volume fractions and centroids (the MoF interfaces of the
!>    paper's Sect. 5.4), and the planes carry them to the next remap);
!>  - after the step's last remap: the burn's start times, the equation of
!>    state of the cells the remaps wrote (the others' pressures are those
!>    the Lagrangian step left, evaluated at this time) and the mixed
!>    cells' pressure and sound speed (`remap_after_state`).
module remap_after
  use base_kinds, only: wp
  use base_errors, only: error_t
  use mesh_grid, only: grid_t
  use hydro_state, only: hydro_t
  use material_table, only: material_t, material_index_cells, material_eval_eos, material_burn_start
  use material_mixed, only: mixed_t, mixed_forget_planes, mixed_cell_state
  use lagrange_centroids, only: centroid_stats_t, plane_memory_t, centroids_fit_planes
  implicit none
  private
  public :: remap_after_planes, remap_after_state

contains

  !> After a remap of grid g: the cell lists of mats from mat and mx, then
  !> every mixed cell's planes forgotten and fitted again (`centroids_fit_
  !> planes`, at most max_iter iterations, each search started from the
  !> plane the cell's material had before the remap, memory). The fits are
  !> counted in stats; with only (mx%n), those of the cells it marks are
  !> fitted first and counted in stats, the others' in others (with kept
  !> (mx%n), only those it marks: the other cells' planes are left
  !> forgotten). written (optional): the cells the remap wrote, the only
  !> ones whose material may have changed (`material_index_cells`).
  subroutine remap_after_planes(g, mats, mat, mx, max_iter, memory, stats, err, only, others, written, kept)
    type(grid_t), intent(in) :: g
    type(material_t), intent(inout) :: mats(:)
    integer, intent(in) :: mat(:)
    type(mixed_t), intent(inout) :: mx
    integer, intent(in) :: max_iter
    type(plane_memory_t), intent(in) :: memory
    type(centroid_stats_t), intent(inout) :: stats
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: only(:)
    type(centroid_stats_t), intent(inout), optional :: others
    integer, intent(in), optional :: written(:)
    logical, intent(in), optional :: kept(:)
    call material_index_cells(mats, mat, mx, err, written)
    if (.not. allocated(err)) call mixed_forget_planes(mx, err)
    if (allocated(err)) return
    if (present(only) .and. present(others)) then
      call centroids_fit_planes(g, mx, stats, max_iter, only=only, memory=memory)
      call centroids_fit_planes(g, mx, others, max_iter, only=kept, memory=memory)
    else
      call centroids_fit_planes(g, mx, stats, max_iter, memory=memory)
    end if
  end subroutine remap_after_planes

  !> After the step's last remap, at time t: the burn's start (`material_
  !> burn_start`), the pressure and sound speed of the cells written (pure
  !> ones by h%mat) and of every mixed-cell slot, then the mixed cells'.
  subroutine remap_after_state(mats, h, mx, written, t)
    type(material_t), intent(inout) :: mats(:)
    type(hydro_t), intent(inout) :: h
    type(mixed_t), intent(inout) :: mx
    integer, intent(in) :: written(:)
    real(wp), intent(in) :: t
    call material_burn_start(mats, t)
    call material_eval_eos(mats, h%rho, h%e, h%p, h%cs, mx, written, h%mat)
    call mixed_cell_state(mx, h%p, h%cs)
  end subroutine remap_after_state
end module remap_after
