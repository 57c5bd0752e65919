!> The &rezone group: whether, when and how an Euler step (rezone, then
!> remap) follows the Lagrangian step.
module rezone_config
  use base_kinds, only: wp
  use base_config, only: max_line, no_echo, problem_long, problem_add, problem_bad, problem_badi, problem_nml
  implicit none
  private
  public :: rezone_config_t, rezone_config_read

  !> The &rezone group: whether, when and how an Euler step (rezone, then
  !> remap) follows the Lagrangian step. An Euler step runs when any trigger
  !> that is on fires.
  type :: rezone_config_t
    !> 'none': pure Lagrangian, no Euler step; 'global': rezone the whole grid
    !> back to the initial one and remap (Eulerian-like global MMALE); 'lssm':
    !> smooth and remap only the distorted subdomains (Sect. 5); 'smooth':
    !> smooth the whole grid and remap (the global MMALE LSSM is measured against)
    character(len=16) :: mode = 'none'
    !> trigger: the largest ratio of side lengths of any cell reaches this
    !> (0: off; else > 1)
    real(wp) :: side_ratio = 4.0_wp
    !> trigger: the smallest cosine of the largest inclined angle over all
    !> cells falls to or below this (0: off; else in (0, 1))
    real(wp) :: cos_angle = 0.7_wp
    integer :: interval_steps = 0          !< trigger: every this many steps (0: off)
    real(wp) :: interval_time = 0.0_wp     !< trigger: every this much simulated time (time; 0: off)
    !> remap reconstruction: 'linear' (limited, second order) or 'constant'
    !> (first order)
    character(len=16) :: reconstruction = 'linear'
    integer :: mof_max_iter = 50           !< cap on MoF Gauss-Newton iterations per material
    !> check mass, momentum and energy conservation to round-off at every
    !> Euler step and stop the run if broken (Debug builds always check)
    !> an Euler step that changes total mass, momentum or energy by more than
    !> this (relative) stops the run: round-off is ~1e-14
    real(wp) :: conservation_tol = 1.0e-10_wp
    ! mode 'lssm' (Sect. 5): only distorted subdomains are smoothed and remapped
    real(wp) :: quality = 0.999_wp         !< a cell with Q (Eq. 46) below this is distorted (the paper's q)
    real(wp) :: quality_target = 0.999_wp  !< smoothing stops when Q_min of the subdomains reaches this
    integer :: smooth_iterations = 20      !< at most this many combined smoothing iterations (N_max)
    !> side of a subdomain's range in cells (0: a tenth of the smallest grid dimension, as the paper)
    real(wp) :: d_max = 0.0_wp
    !> 'lssm', 'smooth': a node the smoothing moves by less than this times its
    !> shortest edge stays where it was (0: every move is kept, as the paper)
    real(wp) :: move_min = 0.0_wp
    !> 'lssm', 'smooth': a node that drifted from its initial place by more
    !> than this times its shortest initial edge is put back there before
    !> the smoothing (0: off; inflow and outflow faces: drift_open)
    real(wp) :: drift_max = 0.0_wp
    !> 'lssm', 'smooth': the same for the nodes of inflow and outflow faces
    !> (0: put back whenever they moved)
    real(wp) :: drift_open = 0.5_wp
    !> the remap's swept-face path (flux form, no intersection) is taken at
    !> an Euler step whose every changed cell is pure, amid cells of its own
    !> material, and moved its nodes by at most this times its shortest
    !> edge; other steps intersect (0: always intersect; the deck's default:
    !> `swept_max_default`)
    real(wp) :: swept_max = 0.25_wp
    !> the swept-face path also through mixed cells, what is swept from them
    !> shared by their MoF planes (a step that breaks a material's bounds is
    !> remapped by intersection); off: mixed cells and the cells next to
    !> another material are intersected (`swept_hybrid`)
    logical :: swept_mixed = .true.
    !> a material below this volume fraction of a cell the swept-face path
    !> remaps is merged into the cell's largest (`remap_params_t`)
    real(wp) :: swept_vf_min = 1.0e-5_wp
    !> an Euler step that could take the swept-face path but for nodes that
    !> move further than swept_max is remapped in up to this many parts of
    !> the way, each by swept faces where it can (1: by intersection; the
    !> deck's default: `swept_parts_default`)
    integer :: swept_parts = 1
    !> an Euler step some of whose changed cells cannot take the swept-face
    !> path is remapped twice: the cells that can by swept faces, then the
    !> others and the cells that share a node with them by intersection
    !> (`remap_hybrid_target`); off: the whole step by intersection
    logical :: swept_hybrid = .true.
    !> a trigger measure an Euler step leaves beyond its bound (side ratio
    !> above side_ratio, cosine below cos_angle) becomes the bound, moved on
    !> by this relative margin, until the grid is back within the deck's
    !> (0: the deck's bounds always)
    real(wp) :: hysteresis = 0.2_wp
    !> 'lssm': 'box' (distorted cells are those failing the triggers' tests;
    !> only their nodes move, towards boxes of the cells' own proportions) or
    !> 'cube' (the paper as printed: Q of Eq. 46 < quality, cubes, TFI)
    character(len=16) :: smooth_target = 'box'
    !> smoothing: the cells whose health (`hex_health`: the smallest corner
    !> Jacobian or 24 tetrahedra of the 24-tet split over the mean edge
    !> cubed; 1 for a cube) is below this are untangled before the passes
    !> (`smooth_untangle`); 0: off
    real(wp) :: untangle = 0.01_wp
    !> 'lssm' with smooth_target 'box': a smoothing pass may not leave a cell
    !> below this share of its volume at the Euler step's start (the guard
    !> takes such a pass back around it, `smooth_region_t`'s squeeze); 0: off
    real(wp) :: squeeze = 0.85_wp
    !> coupled particles: before the remap the fluid under the solid takes
    !> the state of the fluid around it in this many layers of cells from
    !> the solid's surface inwards (`particles_virtual`); 0: it keeps the
    !> state it was carried with
    integer :: virtual_layers = 1
  end type rezone_config_t

contains

  !> Reads, validates and echoes the &rezone group (`text` empty: all
  !> defaults, a purely Lagrangian run). particles: the deck couples
  !> particles (a default depends on it: `swept_parts_default`).
  subroutine rezone_config_read(this, text, path, echo, problems, particles)
    type(rezone_config_t), intent(out) :: this
    character(len=*), intent(in) :: text(:), path
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    logical, intent(in), optional :: particles
    character(len=16) :: mode, reconstruction, smooth_target
    real(wp) :: side_ratio, cos_angle, conservation_tol, interval_time, quality, quality_target, d_max, move_min, &
                drift_max, drift_open, swept_max, hysteresis, swept_vf_min, untangle, squeeze
    integer :: interval_steps, mof_max_iter, smooth_iterations, ios, swept_parts, virtual_layers
    logical :: swept_mixed, swept_hybrid
    character(len=max_line) :: msg
    type(rezone_config_t) :: defaults
    namelist /rezone/ mode, side_ratio, cos_angle, interval_steps, interval_time, reconstruction, &
                      mof_max_iter, conservation_tol, quality, quality_target, smooth_iterations, d_max, &
                      move_min, smooth_target, drift_max, drift_open, swept_max, hysteresis, &
                      swept_mixed, swept_parts, virtual_layers, swept_hybrid, swept_vf_min, untangle, squeeze

    mode = defaults%mode; side_ratio = defaults%side_ratio; cos_angle = defaults%cos_angle
    interval_steps = defaults%interval_steps; interval_time = defaults%interval_time
    reconstruction = defaults%reconstruction; mof_max_iter = defaults%mof_max_iter
    conservation_tol = defaults%conservation_tol
    quality = defaults%quality; quality_target = defaults%quality_target
    smooth_iterations = defaults%smooth_iterations; d_max = defaults%d_max; move_min = defaults%move_min
    smooth_target = defaults%smooth_target; drift_max = defaults%drift_max; drift_open = defaults%drift_open
    hysteresis = defaults%hysteresis; swept_mixed = defaults%swept_mixed
    virtual_layers = defaults%virtual_layers; swept_hybrid = defaults%swept_hybrid
    swept_vf_min = defaults%swept_vf_min; untangle = defaults%untangle; squeeze = defaults%squeeze
    ! (0, and a negative swept_max: the mode's, once the mode is read)
    swept_parts = 0
    swept_max = -1.0_wp
    if (size(text) > 0) then
      read(text, nml=rezone, iostat=ios, iomsg=msg)
      if (ios /= 0) call problem_nml(problems, path, 'rezone', ios, msg)
    end if
    if (swept_parts == 0) then
      if (present(particles)) then
        swept_parts = swept_parts_default(mode, particles)
      else
        swept_parts = swept_parts_default(mode, .false.)
      end if
    end if
    if (swept_max < 0.0_wp) swept_max = swept_max_default(mode)
    call problem_long(problems, 'rezone', 'mode', mode)
    call problem_long(problems, 'rezone', 'reconstruction', reconstruction)
    call problem_long(problems, 'rezone', 'smooth_target', smooth_target)
    select case (trim(smooth_target))
    case ('box', 'cube')
    case default
      call problem_add(problems, '&rezone: smooth_target = '''//trim(smooth_target)//''' is not known; valid: box, cube')
    end select
    select case (trim(mode))
    case ('none', 'global', 'lssm', 'smooth')
    case default
      call problem_add(problems, '&rezone: mode = '''//trim(mode)//''' is not known; valid: none, global, lssm, smooth')
    end select
    select case (trim(reconstruction))
    case ('linear', 'constant')
    case default
      call problem_add(problems, '&rezone: reconstruction = '''//trim(reconstruction)// &
        ''' is not known; valid: linear, constant')
    end select
    if (.not. (side_ratio >= 0.0_wp) .or. (side_ratio > 0.0_wp .and. side_ratio <= 1.0_wp)) &
      call problem_bad(problems, 'rezone', 'side_ratio', side_ratio, 'must be 0 (off) or > 1')
    if (.not. (cos_angle >= 0.0_wp .and. cos_angle < 1.0_wp)) &
      call problem_bad(problems, 'rezone', 'cos_angle', cos_angle, 'must be in [0, 1) (0: off)')
    if (interval_steps < 0) call problem_badi(problems, 'rezone', 'interval_steps', interval_steps, &
      'must be >= 0 (0: off)')
    if (.not. (interval_time >= 0.0_wp)) call problem_bad(problems, 'rezone', 'interval_time', interval_time, &
      'must be >= 0 (0: off)')
    if (.not. (conservation_tol > 0.0_wp .and. conservation_tol < 1.0_wp)) call problem_bad(problems, 'rezone', &
      'conservation_tol', conservation_tol, 'must be in (0, 1)')
    if (mof_max_iter < 1) call problem_badi(problems, 'rezone', 'mof_max_iter', mof_max_iter, 'must be >= 1')
    if (.not. (quality > 0.0_wp .and. quality <= 1.0_wp)) &
      call problem_bad(problems, 'rezone', 'quality', quality, 'must be in (0, 1]')
    if (.not. (quality_target > 0.0_wp .and. quality_target <= 1.0_wp)) &
      call problem_bad(problems, 'rezone', 'quality_target', quality_target, 'must be in (0, 1]')
    if (smooth_iterations < 1) call problem_badi(problems, 'rezone', 'smooth_iterations', smooth_iterations, &
      'must be >= 1')
    if (.not. (d_max >= 0.0_wp)) call problem_bad(problems, 'rezone', 'd_max', d_max, &
      'must be >= 0 (0: a tenth of the smallest grid dimension)')
    if (.not. (move_min >= 0.0_wp .and. move_min < 0.5_wp)) call problem_bad(problems, 'rezone', 'move_min', &
      move_min, 'must be in [0, 0.5) (0: off)')
    if (.not. (drift_max >= 0.0_wp)) call problem_bad(problems, 'rezone', 'drift_max', drift_max, 'must be >= 0 (0: off)')
    if (.not. (drift_open >= 0.0_wp)) call problem_bad(problems, 'rezone', 'drift_open', drift_open, &
      'must be >= 0 (0: open faces put back whenever they moved)')
    if (.not. (hysteresis >= 0.0_wp .and. hysteresis < 1.0_wp)) call problem_bad(problems, 'rezone', 'hysteresis', &
      hysteresis, 'must be in [0, 1) (0: off)')
    if (.not. (swept_max >= 0.0_wp .and. swept_max <= 0.5_wp)) call problem_bad(problems, 'rezone', 'swept_max', &
      swept_max, 'must be in [0, 0.5] (0: always intersect)')
    if (.not. (swept_vf_min >= 0.0_wp .and. swept_vf_min <= 1.0e-2_wp)) call problem_bad(problems, 'rezone', &
      'swept_vf_min', swept_vf_min, 'must be in [0, 0.01]')
    if (.not. (untangle >= 0.0_wp .and. untangle < 1.0_wp)) call problem_bad(problems, 'rezone', 'untangle', &
      untangle, 'must be in [0, 1) (0: off)')
    if (.not. (squeeze >= 0.0_wp .and. squeeze < 1.0_wp)) call problem_bad(problems, 'rezone', 'squeeze', &
      squeeze, 'must be in [0, 1) (0: off)')
    if (virtual_layers < 0) call problem_badi(problems, 'rezone', 'virtual_layers', virtual_layers, &
      'must be >= 0 (0: off)')
    if (swept_parts < 1 .or. swept_parts > 64) call problem_badi(problems, 'rezone', 'swept_parts', swept_parts, &
      'must be in [1, 64] (1: off; 0: the mode''s default)')
    if (trim(mode) /= 'none' .and. .not. (side_ratio > 0.0_wp .or. cos_angle > 0.0_wp .or. &
                                            interval_steps > 0 .or. interval_time > 0.0_wp)) &
      call problem_add(problems, '&rezone: mode = '''//trim(mode)//''' needs a trigger; set side_ratio > 1, '// &
        'cos_angle > 0, interval_steps > 0 or interval_time > 0')
    this = rezone_config_t(mode=mode, side_ratio=side_ratio, cos_angle=cos_angle, &
      interval_steps=interval_steps, interval_time=interval_time, reconstruction=reconstruction, &
      mof_max_iter=mof_max_iter, conservation_tol=conservation_tol, quality=quality, &
      quality_target=quality_target, smooth_iterations=smooth_iterations, d_max=d_max, move_min=move_min, &
      smooth_target=smooth_target, drift_max=drift_max, drift_open=drift_open, &
      swept_max=swept_max, hysteresis=hysteresis, swept_mixed=swept_mixed, swept_parts=swept_parts, &
      virtual_layers=virtual_layers, swept_hybrid=swept_hybrid, swept_vf_min=swept_vf_min, untangle=untangle, &
      squeeze=squeeze)
    if (echo /= no_echo) write(echo, nml=rezone)
  end subroutine rezone_config_read

  !> &rezone swept_max when the deck does not set it (or sets a negative
  !> value): 0.5 in mode 'global', whose Eulerian steps at the stable step
  !> move a node up to cfl u/(u + c) of a cell (a third of it behind a
  !> strong shock in air at cfl 0.5: every such step would intersect at
  !> 0.25); 0.25 for the smoothing modes, which take their far moves in
  !> parts (`swept_parts`), and where 0.5 measured slower (the TNT octant at
  !> 16^3 in LSSM 9.0 s against 5.2 s, the paper's Sedov at 20^3 7.1 s
  !> against 3.4 s).
  pure real(wp) function swept_max_default(mode) result(r)
    character(len=*), intent(in) :: mode
    r = 0.5_wp
    if (trim(mode) == 'lssm' .or. trim(mode) == 'smooth') r = 0.25_wp
  end function swept_max_default

  !> &rezone swept_parts when the deck does not set it (or sets 0): 16 for
  !> the smoothing modes ('lssm', 'smooth'), whose smoothing moves the nodes
  !> of a compressed shell several times its short edges (in parts by swept
  !> faces the paper's Sedov at 20^3 spends 12 % of the Euler phase LSSM
  !> spends by intersection, and 6 % for 'smooth', at the same L1 error, as
  !> the deck documentation in input/ gives it); 4 for 'global' with coupled
  !> particles (particles), whose Euler steps every few steps let a flow
  !> carry the nodes further than the swept faces take at once (the
  !> flexible plate: its Euler phase in half the time, the same answers
  !> within about 1 %, input/README.md); off for the others (the Noh
  !> problem in ALE mode diffuses through the parts' repeated remaps).
  pure integer function swept_parts_default(mode, particles) result(n)
    character(len=*), intent(in) :: mode
    logical, intent(in) :: particles
    n = 1
    if (trim(mode) == 'lssm' .or. trim(mode) == 'smooth') n = 16
    if (trim(mode) == 'global' .and. particles) n = 4
  end function swept_parts_default
end module rezone_config
