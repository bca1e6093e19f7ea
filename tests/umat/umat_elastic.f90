! Reference UMAT 1 of the umat adapter's tests: isotropic linear elasticity, small strains.
! Written for Stratum from the equations (no other UMAT was copied):
!   lambda = E nu / ((1 + nu)(1 - 2 nu)),  G = E / (2 (1 + nu))
!   sigma_ij = sigma_ij,n + lambda tr(d eps) delta_ij + 2 G d eps_ij
! In Abaqus' layout (NDI direct components, then NSHR engineering shear strains):
!   DDSDDE(i, j) = lambda + 2 G delta_ij for i, j <= NDI;  DDSDDE(k, k) = G for k > NDI.
! PROPS(1) = E (kPa), PROPS(2) = nu. No state variables. SSE accumulates the strain energy.
subroutine umat(stress, statev, ddsdde, sse, spd, scd, rpl, ddsddt, drplde, drpldt, &
                stran, dstran, time, dtime, temp, dtemp, predef, dpred, cmname, &
                ndi, nshr, ntens, nstatv, props, nprops, coords, drot, pnewdt, &
                celent, dfgrd0, dfgrd1, noel, npt, layer, kspt, kstep, kinc)
  implicit none
  character(len=80), intent(in) :: cmname
  integer, intent(in) :: ndi, nshr, ntens, nstatv, nprops, noel, npt, layer, kspt, kstep, kinc
  double precision, intent(inout) :: stress(ntens), statev(*), ddsdde(ntens, ntens)
  double precision, intent(inout) :: sse, spd, scd, rpl, ddsddt(ntens), drplde(ntens), drpldt
  double precision, intent(in) :: stran(ntens), dstran(ntens), time(2), dtime, temp, dtemp
  double precision, intent(in) :: predef(*), dpred(*), props(nprops), coords(3), drot(3, 3)
  double precision, intent(inout) :: pnewdt
  double precision, intent(in) :: celent, dfgrd0(3, 3), dfgrd1(3, 3)

  double precision :: e, nu, lam, g, old(6)
  integer :: i, j

  e = props(1)
  nu = props(2)
  lam = e * nu / ((1.0d0 + nu) * (1.0d0 - 2.0d0 * nu))
  g = e / (2.0d0 * (1.0d0 + nu))

  ddsdde = 0.0d0
  do i = 1, ndi
    do j = 1, ndi
      ddsdde(i, j) = lam
    end do
    ddsdde(i, i) = lam + 2.0d0 * g
  end do
  do i = ndi + 1, ntens
    ddsdde(i, i) = g
  end do

  old(1:ntens) = stress
  do i = 1, ntens
    do j = 1, ntens
      stress(i) = stress(i) + ddsdde(i, j) * dstran(j)
    end do
  end do
  sse = sse + 0.5d0 * dot_product(old(1:ntens) + stress, dstran)
end subroutine umat
