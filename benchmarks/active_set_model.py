#!/usr/bin/python3
"""1D model study of active-set strategies for the enthalpy step (doc/algorithms.md, section 2).

Plain active set, one-state-per-iteration limit, nested Newton (Brugnano & Casulli)
and the Armijo line search on the convex functional E, on a 1D lumped-mass Q1 chain
melted from x = 0. Needs numpy (Debian: python3-numpy). Prints failures and mean
solves per step for each configuration. Prototype code: the C++ implementation is
source/thermal/thermal_field/enthalpy_step.cc."""
import numpy as np

class Law:
    def __init__(s, T, L, c):
        s.T=np.array(T,float); s.L=np.array(L,float); s.c=np.array(c,float); n=len(T)
        s.off=np.zeros(n+1); s.hm=np.zeros(n); s.hp=np.zeros(n)
        s.off[0]=-s.c[0]*s.T[0]
        for j in range(n):
            s.hm[j]=s.off[j]+s.c[j]*s.T[j]; s.hp[j]=s.hm[j]+s.L[j]; s.off[j+1]=s.hp[j]-s.c[j+1]*s.T[j]
    def state(s,h):
        for j in range(len(s.T)):
            if h < s.hm[j]: return 2*j
            if h <= s.hp[j]: return 2*j+1
        return 2*len(s.T)
    def piece(s,st):
        if st%2: return (True, s.T[st//2], 0, 0)
        return (False, 0, s.c[st//2], s.off[st//2])
    def enthalpy(s,th):
        for j in range(len(s.T)):
            if th < s.T[j]: return s.off[j]+s.c[j]*th
            if th == s.T[j]: return s.hm[j]
        return s.off[-1]+s.c[-1]*th
    def beta(s,h):
        st=s.state(h); p=s.piece(st)
        return p[1] if p[0] else (h-p[3])/p[2]
    def outer(s,h):
        J=0
        while J<len(s.T) and h>s.hm[J]: J+=1
        return J
    def npiece_of(s,J,h):
        k = 0 if J==0 else J-1
        while k<len(s.T) and h>s.hp[k]: k+=1
        return k
    def npiece(s,J,k):
        if J>=1 and k==J-1: return (True, s.T[J-1],0,0)
        ha = s.hm[0] if J==0 else s.hp[J-1]; ta = s.T[0 if J==0 else J-1]; d=1/s.c[J]
        for i in range(J,k):
            ta += d*(s.hp[i]-ha); ha=s.hp[i]; d+=1/s.c[i+1]
        cap=1/d; return (False,0,cap,ha-cap*ta)

def solve_pieces(A, m, tau, hold, F, pieces, dirichlet):
    n=len(m); K=tau*A.copy(); b=m*hold+tau*F
    fixed={}
    for i in range(n):
        if i in dirichlet: fixed[i]=dirichlet[i]; continue
        p=pieces[i]
        if p[0]: fixed[i]=p[1]
        else: K[i,i]+=m[i]*p[2]; b[i]-=m[i]*p[3]
    free=[i for i in range(n) if i not in fixed]
    th=np.zeros(n)
    for i,v in fixed.items(): th[i]=v
    fi=list(fixed)
    bb=b[free]-K[np.ix_(free,fi)]@th[fi]
    th[free]=np.linalg.solve(K[np.ix_(free,free)],bb)
    Ath=A@th; h=np.zeros(n)
    for i in range(n):
        if i in dirichlet: h[i]=None
        elif pieces[i][0]: h[i]=hold[i]+tau*(F[i]-Ath[i])/m[i]
        else: h[i]=pieces[i][3]+pieces[i][2]*th[i]
    return th,h

def plain(law,A,m,tau,hold,F,dirichlet,states,maxit=50):
    n=len(m)
    for it in range(1,maxit+1):
        th,h=solve_pieces(A,m,tau,hold,F,[law.piece(s) for s in states],dirichlet)
        new=[states[i] if i in dirichlet else law.state(h[i]) for i in range(n)]
        ch=sum(a!=b for a,b in zip(new,states)); states=new
        if ch==0: return it,th,h,states
    return None,th,h,states

def nested(law,A,m,tau,hold,F,dirichlet,h0,maxit=60, verbose=False):
    n=len(m)
    J=[0 if i in dirichlet else law.outer(h0[i]) for i in range(n)]
    k=[0 if i in dirichlet else law.npiece_of(J[i],h0[i]) for i in range(n)]
    for it in range(1,maxit+1):
        th,h=solve_pieces(A,m,tau,hold,F,[law.npiece(J[i],k[i]) for i in range(n)],dirichlet)
        nk=[k[i] if i in dirichlet else law.npiece_of(J[i],h[i]) for i in range(n)]
        ci=sum(a!=b for a,b in zip(nk,k)); k=nk; co=0
        if ci==0:
            nJ=[J[i] if i in dirichlet else law.outer(h[i]) for i in range(n)]
            co=sum(a!=b for a,b in zip(nJ,J)); 
            if verbose: print("   outer changes", [(i,J[i],nJ[i]) for i in range(n) if J[i]!=nJ[i]])
            J=nJ
            k=[k[i] if i in dirichlet else law.npiece_of(J[i],h[i]) for i in range(n)]
        if verbose: print("  it",it,"inner",ci,"outer",co)
        if ci==0 and co==0: return it,th,h
    return None,th,h

def plain_verbose(law,A,m,tau,hold,F,dirichlet,states,maxit=8):
    n=len(m)
    for it in range(1,maxit+1):
        th,h=solve_pieces(A,m,tau,hold,F,[law.piece(s) for s in states],dirichlet)
        new=[states[i] if i in dirichlet else law.state(h[i]) for i in range(n)]
        print("  it",it,[(i,states[i],new[i],round(th[i],4),round(h[i],4)) for i in range(n) if new[i]!=states[i]])
        if new==states: return
        states=new

def plain_limited(law,A,m,tau,hold,F,dirichlet,states,maxit=50,limit=1):
    n=len(m)
    for it in range(1,maxit+1):
        th,h=solve_pieces(A,m,tau,hold,F,[law.piece(s) for s in states],dirichlet)
        new=[]
        for i in range(n):
            if i in dirichlet: new.append(states[i]); continue
            s=law.state(h[i]); o=states[i]
            s=max(o-limit,min(o+limit,s))
            new.append(s)
        if new==states: return it,th,h,states
        states=new
    return None,th,h,states

def Psi(law,h):
    # primitive of beta, from h = hm[0] (or 0)
    n=len(law.T)
    if n==0: return 0.5*h*h/law.c[0]
    # breakpoints in h: hm0, hp0, hm1, hp1...
    pts=[]; 
    for j in range(n): pts += [law.hm[j], law.hp[j]]
    val=0.0; a=law.hm[0]
    # integrate from a to h piecewise
    def beta(x): return law.beta(x)
    lo,hi,sgn=(a,h,1) if h>=a else (h,a,-1)
    cuts=[lo]+[p for p in pts if lo<p<hi]+[hi]
    for x0,x1 in zip(cuts[:-1],cuts[1:]):
        val += 0.5*(beta(x0)+beta(x1))*(x1-x0)   # beta linear on each piece
    return sgn*val

def damped(law,A,m,tau,hold,F,dirichlet,states,maxit=60,sigma=1e-4,verbose=False):
    n=len(m); free=[i for i in range(n) if i not in dirichlet]
    h=None; z=None
    for it in range(1,maxit+1):
        th,hn=solve_pieces(A,m,tau,hold,F,[law.piece(s) for s in states],dirichlet)
        if h is None:
            h=hn.copy(); z=-th.copy(); alpha=1.0
        else:
            dh=np.zeros(n); dh[free]=hn[free]-h[free]
            d=m*dh; w=-z-th
            b=np.array([law.beta(h[i]) if i in free else 0 for i in range(n)])
            slope=sum((z[i]+b[i])*d[i] for i in free)
            alpha=1.0
            while True:
                dE=alpha*sum(d[i]*z[i] for i in free)+0.5*alpha**2*sum(d[i]*w[i] for i in free)\
                   +sum(m[i]*(Psi(law,h[i]+alpha*dh[i])-Psi(law,h[i])) for i in free)
                if dE<=sigma*alpha*slope or alpha<1e-8: break
                alpha*=0.5
            for i in free: h[i]+=alpha*dh[i]
            z=(1-alpha)*z-alpha*th
        new=[states[i] if i in dirichlet else law.state(h[i]) for i in range(n)]
        if verbose: print("   it",it,"alpha",alpha,"changes",sum(a!=b for a,b in zip(new,states)))
        if new==states and alpha==1.0: return it,th,hn
        states=new
    return None,th,h


def experiment(N, X, tau, law, Thot, Tcold, steps, k=1.0):
    hx=X/N; n=N+1
    A=np.zeros((n,n)); m=np.zeros(n)
    for e in range(N):
        A[e:e+2,e:e+2]+=k/hx*np.array([[1,-1],[-1,1]]); m[e:e+2]+=hx/2
    h=np.array([law.enthalpy(Tcold)]*n); h[0]=law.enthalpy(Thot)
    states=[law.state(v) for v in h]; dir_={0:Thot,N:Tcold}; F=np.zeros(n)
    res={'plain':[], 'lim':[], 'nested':[], 'damped':[]}
    hprev=h.copy()
    for step in range(steps):
        hold=h.copy()
        hpred=hold+(hold-hprev) if step>0 else hold
        st0=[law.state(v) for v in hpred]
        a=plain(law,A,m,tau,hold,F,dir_,list(st0))[0]
        b,thb,hb,_=plain_limited(law,A,m,tau,hold,F,dir_,list(st0))
        c,thc,hc=nested(law,A,m,tau,hold,F,dir_,hpred)
        d_=damped(law,A,m,tau,hold,F,dir_,list(st0))[0]; res['damped'].append(d_)
        res['plain'].append(a); res['lim'].append(b); res['nested'].append(c)
        hprev=hold
        h=hc; h[0]=law.enthalpy(Thot); h[N]=law.enthalpy(Tcold)
        if b is not None and c is not None:
            assert np.max(np.abs(thb-thc))<1e-9, np.max(np.abs(thb-thc))
    for key,v in res.items():
        fails=sum(x is None for x in v); ok=[x for x in v if x is not None]
        print(f"  {key:7s} fails {fails:3d}  mean {np.mean(ok) if ok else -1:.2f} max {max(ok) if ok else -1}")
law2=Law([0,0.5],[1,0.5],[1,1.2,0.8]); law1=Law([0],[1],[1,1])
for tau in [1/16, 1/4]:
  for N in [64,256]:
    print("two transitions N",N,"tau",tau); experiment(N,4.0,tau,law2,1.5,-1.0,40)
    print("one transition N",N,"tau",tau); experiment(N,4.0,tau,law1,1.0,-1.0,40)
